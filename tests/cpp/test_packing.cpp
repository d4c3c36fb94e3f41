#include "common/suspension.hpp"
#include "dynamics/packing.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

namespace {
double box_for(int m, double phi) {
  return periodic_box_side(m, phi);
}
} // namespace

TEST_CASE("packing: the box side and the particle-stress factor of the conventions",
          "[packing]") {
  // One sphere of volume 4 pi / 3 at phi = pi / 6 fills a cube of side 2.
  CHECK(periodic_box_side(1, kPi / 6) == Approx(2.0).epsilon(1e-15));
  CHECK(periodic_box_side(8, kPi / 6) == Approx(4.0).epsilon(1e-15));
  // 3 phi / (4 pi Ca) = 1 at phi = 4 pi / 30, Ca = 0.1; phi = 0 leaves phi out.
  CHECK(particle_stress_factor(4 * kPi / 30, 0.1) == Approx(1.0).epsilon(1e-15));
  CHECK(particle_stress_factor(0, 0.2) == Approx(3 / (0.8 * kPi)).epsilon(1e-15));
}

TEST_CASE("packing: 100 capsules at phi = 0.45 without overlap, reproducibly",
          "[packing]") {
  PackingOptions o;
  o.capsules = 100;
  o.box = box_for(100, 0.45);
  o.min_gap = 0.05;
  o.seed = 7;
  auto c = pack_spheres(o);
  REQUIRE(c.size() == 100);
  CHECK(min_pair_distance(c, o.box) >= 2.05 - 1e-9);
  for (const auto& p : c) {
    CHECK(p.x >= 0);
    CHECK(p.x < o.box);
  }
  auto again = pack_spheres(o);
  CHECK(again[42].y == c[42].y);
  o.seed = 8;
  CHECK(pack_spheres(o)[42].y != c[42].y);
}

TEST_CASE("packing: an impossible volume fraction is refused with a reason",
          "[packing]") {
  PackingOptions o;
  o.capsules = 100;
  o.box = box_for(100, 0.62);
  CHECK_THROWS_WITH(pack_spheres(o), Catch::Contains("cannot pack 100 capsules"));
}
