// The optional repulsion between capsules: the force law, Newton's third law, periodic
// images, and that nodes of one capsule never repel each other.
#include "dynamics/repulsion.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

TEST_CASE("repulsion: force (1 - d/range)^2 between capsules, equal and opposite, "
          "across the periodic boundary",
          "[repulsion]") {
  const ShearedLattice g = make_sheared_lattice(5.0, 0.3);
  RepulsionOptions r;
  r.range = 0.2;
  r.force = 2.0;
  // Two capsules of two nodes each. Capsule 0: nodes 0, 1; capsule 1: nodes 2, 3.
  // Node 0 near x = L/2 and node 2 just across the boundary (image 0.05 away along x);
  // node 1 is 0.1 from node 0 (same capsule: no force); node 3 is far from everything.
  std::vector<Vec3> x = {
      {2.48, 1.0, 1.0}, {2.38, 1.0, 1.0}, {-2.47, 1.0, 1.0}, {0.0, -2.0, -2.0}};
  std::vector<Vec3> grad(x.size());
  std::vector<int> repelled;
  add_repulsion_gradient(g, 2, x, r, grad, &repelled);
  const double d02 = 0.05, d12 = 0.15;
  const double f0 = r.force * (1 - d02 / r.range) * (1 - d02 / r.range);
  const double f1 = r.force * (1 - d12 / r.range) * (1 - d12 / r.range);
  // The force -grad pushes node 0 (and node 1) away from node 2's image at x = 2.53.
  CHECK(-grad[0].x == Approx(-f0).epsilon(1e-12));
  CHECK(-grad[1].x == Approx(-f1).epsilon(1e-12));
  CHECK(-grad[2].x == Approx(f0 + f1).epsilon(1e-12));
  CHECK(grad[0].y == Approx(0).margin(1e-14));
  CHECK(norm(grad[3]) == 0.0);
  CHECK(norm(grad[0] + grad[1] + grad[2] + grad[3]) < 1e-12);
  CHECK(repelled == std::vector<int>{2, 1});
}

TEST_CASE("repulsion: the gradient is that of the pair energy (finite differences)",
          "[repulsion]") {
  const ShearedLattice g = make_sheared_lattice(4.0, -0.2);
  RepulsionOptions r;
  r.range = 0.3;
  r.force = 1.5;
  const std::vector<Vec3> x = {
      {0.1, 0.2, 0.3}, {0.9, 0.9, 0.9}, {0.25, 0.3, 0.2}, {0.3, 0.1, 0.45}};
  auto energy = [&](const std::vector<Vec3>& p) {
    double e = 0; // pairs of different capsules (2 nodes each), no images this close
    for (int i : {0, 1})
      for (int j : {2, 3}) {
        const double d = norm(p[i] - p[j]);
        if (d < r.range)
          e += r.force * r.range / 3 * std::pow(1 - d / r.range, 3);
      }
    return e;
  };
  std::vector<Vec3> grad(x.size());
  add_repulsion_gradient(g, 2, x, r, grad);
  const double h = 1e-6;
  for (int i = 0; i < 4; ++i)
    for (int a = 0; a < 3; ++a) {
      auto plus = x, minus = x;
      (&plus[i].x)[a] += h;
      (&minus[i].x)[a] -= h;
      const double fd = (energy(plus) - energy(minus)) / (2 * h);
      CHECK((&grad[i].x)[a] == Approx(fd).margin(1e-8));
    }
}
