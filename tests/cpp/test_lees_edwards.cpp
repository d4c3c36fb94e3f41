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

TEST_CASE("lees-edwards: closest approach equals the brute-force search below its reach",
          "[lees-edwards]") {
  // Three wobbly capsules of a sheared box: 0 and 1 nearly touch across the y boundary
  // (1's image at y - L is shifted by -s L in x), 2 is far from both. The lens search
  // must find the brute-force minimum over all nodes and images.
  Icosphere s = make_icosphere(2);
  const int nn = s.topology.num_nodes;
  const double L = 6.0, reach = 0.5;
  ShearedLattice g = make_sheared_lattice(L, 0.4);
  const Vec3 centres[3] = {{0.3, 0.4, 3.0}, {3.1, 4.25, 3.1}, {3.2, 2.0, 0.2}};
  std::vector<Vec3> x;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < nn; ++i) {
      const Vec3& p = s.positions[i];
      double wobble = 1.0 + 0.08 * std::sin(3 * p.x + 5 * p.y + c) * std::cos(4 * p.z);
      x.push_back(Vec3{1.1 * p.x, 0.9 * p.y, p.z} * wobble + centres[c]);
    }
  double brute = 1e300;
  int brute_a = -1, brute_b = -1;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      for (int n1 = -1; n1 <= 1; ++n1)
        for (int n2 = -1; n2 <= 1; ++n2)
          for (int n3 = -1; n3 <= 1; ++n3) {
            Vec3 shift = lattice_point(g, n1, n2, n3);
            for (int i = 0; i < nn; ++i)
              for (int j = 0; j < nn; ++j) {
                double d = norm(x[b * nn + j] + shift - x[a * nn + i]);
                if (d < brute)
                  brute = d, brute_a = a, brute_b = b;
              }
          }
  REQUIRE(brute < reach); // the case is built so that the search must find something
  ClosestApproach c = closest_approach(s.topology, 3, g, x, reach);
  CHECK(c.distance == Approx(brute).epsilon(1e-12)); // the shift is rounded differently
  CHECK(c.capsule_a == brute_a);
  CHECK(c.capsule_b == brute_b);
  // With a reach below the gap nothing is close: the answer is at least that reach.
  CHECK(closest_approach(s.topology, 3, g, x, 0.5 * brute).distance >= 0.5 * brute);
}

namespace {

// The brute-force closest approach over every pair (a <= b) and every image within two
// cells (a capsule against its own images but not itself).
ClosestApproach brute_closest(const std::vector<Vec3>& x, int nn, int capsules,
                              const ShearedLattice& g) {
  ClosestApproach best;
  for (int a = 0; a < capsules; ++a)
    for (int b = a; b < capsules; ++b)
      for (int n1 = -2; n1 <= 2; ++n1)
        for (int n2 = -2; n2 <= 2; ++n2)
          for (int n3 = -2; n3 <= 2; ++n3) {
            if (a == b && n1 == 0 && n2 == 0 && n3 == 0)
              continue;
            const Vec3 shift = lattice_point(g, n1, n2, n3);
            for (int i = 0; i < nn; ++i)
              for (int j = 0; j < nn; ++j) {
                const double d = norm(x[b * nn + j] + shift - x[a * nn + i]);
                if (d < best.distance)
                  best = {d, a, b};
              }
          }
  return best;
}

} // namespace

TEST_CASE("lees-edwards: in a box little larger than the capsules, closest approach sees "
          "every image, and a capsule's own",
          "[lees-edwards]") {
  Icosphere s = make_icosphere(2);
  const int nn = s.topology.num_nodes;
  const double reach = 0.3;
  SECTION("a capsule longer than the box is wide touches its own image") {
    const double L = 3.45;
    const ShearedLattice g = make_sheared_lattice(L, 0.25);
    std::vector<Vec3> x;
    for (const auto& p : s.positions)
      x.push_back(Vec3{1.7 * p.x, 0.8 * p.y, 0.8 * p.z} + Vec3{1.7, 1.7, 1.7});
    const ClosestApproach brute = brute_closest(x, nn, 1, g);
    REQUIRE(brute.distance < reach);
    const ClosestApproach c = closest_approach(s.topology, 1, g, x, reach);
    CHECK(c.distance == Approx(brute.distance).epsilon(1e-12));
    CHECK(c.capsule_a == 0);
    CHECK(c.capsule_b == 0);
  }
  SECTION("two tilted capsules that reach each other through several images") {
    const double L = 3.6;
    const ShearedLattice g = make_sheared_lattice(L, -0.35);
    const Vec3 centres[2] = {{0.4, 0.5, 1.2}, {2.3, 2.2, 1.9}};
    std::vector<Vec3> x;
    for (int c = 0; c < 2; ++c)
      for (const auto& p : s.positions) {
        // Elongated along a direction tilted in x-y, the second the other way.
        const double t = c == 0 ? 0.6 : -0.7;
        const Vec3 q{1.45 * p.x, 0.75 * p.y, 0.8 * p.z};
        x.push_back(Vec3{std::cos(t) * q.x - std::sin(t) * q.y,
                         std::sin(t) * q.x + std::cos(t) * q.y, q.z} +
                    centres[c]);
      }
    const ClosestApproach brute = brute_closest(x, nn, 2, g);
    REQUIRE(brute.distance < reach);
    const ClosestApproach c = closest_approach(s.topology, 2, g, x, reach);
    CHECK(c.distance == Approx(brute.distance).epsilon(1e-12));
    CHECK(c.capsule_a == brute.capsule_a);
    CHECK(c.capsule_b == brute.capsule_b);
  }
}
