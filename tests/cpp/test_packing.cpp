#include "dynamics/packing.hpp"
#include "stokes/stokeslet.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

namespace {
double box_for(int m, double phi) {
  return std::cbrt(m * 4.0 * kPi / (3.0 * phi));
}
} // namespace

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
