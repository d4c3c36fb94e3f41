#include "diagnostics/capsule_diagnostics.hpp"
#include "mesh/icosphere.hpp"
#include "mesh/surface_geometry.hpp"
#include "stokes/kernels/stokeslet.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

TEST_CASE("mesh: icosphere sizes match the paper's meshes", "[mesh]") {
  const int elements[] = {320, 1280, 5120}, nodes[] = {162, 642, 2562};
  for (int level = 2; level <= 4; ++level) {
    Icosphere s = make_icosphere(level);
    CHECK(s.topology.triangles.size() == size_t(elements[level - 2]));
    CHECK(s.topology.num_nodes == nodes[level - 2]);
    for (const auto& p : s.positions)
      CHECK(norm(p) == Approx(1.0).epsilon(1e-14));
  }
  CHECK_THROWS_WITH(make_icosphere(9),
                    Catch::Contains("mesh_level") && Catch::Contains("[0, 6]"));
}

TEST_CASE("mesh: volume converges to 4 pi / 3 at second order", "[mesh]") {
  double err[3];
  for (int level = 2; level <= 4; ++level) {
    Icosphere s = make_icosphere(level);
    double v = enclosed_volume(s.topology, s.positions.data());
    REQUIRE(v > 0); // outward orientation
    err[level - 2] = std::abs(v - 4.0 * kPi / 3.0);
  }
  CHECK(testing::observed_order(err[0], err[1]) == Approx(2.0).margin(0.1));
  CHECK(testing::observed_order(err[1], err[2]) == Approx(2.0).margin(0.1));
}

TEST_CASE("mesh: centroid and isotropic second moment of the icosphere", "[mesh]") {
  Icosphere s = make_icosphere(3);
  Vec3 c = volume_centroid(s.topology, s.positions.data());
  CHECK(norm(c) < 1e-14);
  Mat3 mo = second_moment(s.topology, s.positions.data(), c);
  // Icosahedral symmetry makes the second moment exactly isotropic.
  CHECK(mo.m[0][0] == Approx(mo.m[1][1]).epsilon(1e-12));
  CHECK(mo.m[0][0] == Approx(mo.m[2][2]).epsilon(1e-12));
  CHECK(std::abs(mo.m[0][1]) < 1e-14);
  CHECK(mo.m[0][0] == Approx(4.0 * kPi / 15.0).epsilon(2e-2)); // sphere value, O(h^2)
}

TEST_CASE("diagnostics: Taylor parameter and angle of a sheared ellipsoid are exact",
          "[diagnostics]") {
  // The affine image of an isotropic body has second moment A Mo A^T, so D and theta_D
  // of a stretched icosphere equal those of the ellipsoid to round-off.
  Icosphere s = make_icosphere(2);
  for (double angle_deg : {-60.0, 0.0, 27.0, 89.0}) {
    auto x = testing::stretched(s.positions, 1.4, 0.8, 0.9, angle_deg * kPi / 180.0);
    Vec3 c = volume_centroid(s.topology, x.data());
    TaylorDeformation td = taylor_deformation(second_moment(s.topology, x.data(), c));
    CHECK(td.D == Approx((1.4 - 0.8) / (1.4 + 0.8)).epsilon(1e-12));
    CHECK(td.theta_deg == Approx(angle_deg).margin(1e-9));
  }
}

TEST_CASE("mesh: node areas sum to the surface area, normals are unit and outward",
          "[mesh]") {
  Icosphere s = make_icosphere(3);
  auto a = node_areas(s.topology, s.positions.data());
  double sum = 0;
  for (double v : a)
    sum += v;
  CHECK(sum == Approx(surface_area(s.topology, s.positions.data())).epsilon(1e-13));
  auto n = node_normals(s.topology, s.positions.data());
  for (int i = 0; i < s.topology.num_nodes; ++i) {
    CHECK(norm(n[i]) == Approx(1.0));
    CHECK(dot(n[i], s.positions[i]) > 0.99);
  }
}
