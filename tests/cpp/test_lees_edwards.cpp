#include "dynamics/lees_edwards.hpp"
#include "mesh/surface_geometry.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

TEST_CASE("lees-edwards: a capsule leaving through y = L re-enters shifted by -s L in x",
          "[lees-edwards]") {
  Icosphere s = make_icosphere(1);
  const double L = 5.0;
  ShearedLattice g = make_sheared_lattice(L, 0.3);
  std::vector<Vec3> x;
  const Vec3 c0{1.0, 5.2, 2.0}; // centroid just above the top boundary
  for (const auto& p : s.positions)
    x.push_back(p + c0);
  auto before = x;
  CHECK(remap_capsules(s.topology, 1, g, x) == 1);
  Vec3 c = volume_centroid(s.topology, x.data());
  CHECK(c.y == Approx(0.2));
  // The Lees-Edwards offset -s L, then one box length to land in the primary cell.
  CHECK(c.x == Approx(1.0 - 0.3 * L + L));
  CHECK(c.z == Approx(2.0));
  for (size_t i = 0; i < x.size(); ++i) // moved whole: the shape is unchanged
    CHECK(norm((x[i] - c) - (before[i] - c0)) < 1e-12);
  CHECK(remap_capsules(s.topology, 1, g, x) == 0); // now inside: nothing to do
}

TEST_CASE("lees-edwards: closest approach sees neighbours across the boundary",
          "[lees-edwards]") {
  Icosphere s = make_icosphere(1);
  const double L = 5.0;
  ShearedLattice g = make_sheared_lattice(L, 0.0);
  std::vector<Vec3> x;
  for (const auto& p : s.positions)
    x.push_back(p + Vec3{0.5, 2.5, 2.5});
  for (const auto& p : s.positions)
    x.push_back(p + Vec3{4.2, 2.5, 2.5}); // 1.3 apart via x = 0
  ClosestApproach c = closest_approach(s.topology, 2, g, x, 0.5);
  CHECK(c.capsule_a == 0);
  CHECK(c.capsule_b == 1);
  double expected = 1e300; // brute force with capsule 1's image at x - L
  for (int i = 0; i < s.topology.num_nodes; ++i)
    for (int j = 0; j < s.topology.num_nodes; ++j)
      expected =
          std::min(expected, norm(x[s.topology.num_nodes + j] - Vec3{L, 0, 0} - x[i]));
  CHECK(c.distance == Approx(expected));
  CHECK(c.distance < 1.3);
}
