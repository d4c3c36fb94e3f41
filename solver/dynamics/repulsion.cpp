#include "dynamics/repulsion.hpp"

#include "stokes/periodic_cells.hpp"

#include <cmath>

namespace capsim {

void add_repulsion_gradient(const ShearedLattice& g, int nodes_per_capsule,
                            const std::vector<Vec3>& x, const RepulsionOptions& r,
                            std::vector<Vec3>& grad, std::vector<int>* repelled) {
  const int n = int(x.size()), num_capsules = n / nodes_per_capsule;
  if (repelled)
    repelled->assign(num_capsules, 0);
  const PeriodicCells cells(g, r.range, x);
  std::vector<char> near(n, 0);
  // Each node sums the forces of its own partners: every pair is visited from both
  // sides, and the result does not depend on the thread count.
#pragma omp parallel for schedule(dynamic, 64)
  for (int i = 0; i < n; ++i) {
    const int capsule = i / nodes_per_capsule;
    Vec3 sum;
    cells.for_neighbours(x[i], [&](int j, Vec3 image) {
      if (j / nodes_per_capsule == capsule)
        return;
      const Vec3 d = x[i] - image;
      const double dist = norm(d);
      if (dist >= r.range || dist == 0)
        return;
      const double s = 1.0 - dist / r.range;
      sum += (-r.force * s * s / dist) * d; // dE/dx_i = -force (1 - d/range)^2 d/|d|
      near[i] = 1;
    });
    grad[i] += sum;
  }
  if (repelled)
    for (int i = 0; i < n; ++i)
      (*repelled)[i / nodes_per_capsule] += near[i];
}

} // namespace capsim
