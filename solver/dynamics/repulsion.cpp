#include "dynamics/repulsion.hpp"

#include "dynamics/bounding_spheres.hpp"
#include "stokes/cells/periodic_cells.hpp"

#include <algorithm>
#include <cmath>

namespace capsim {

namespace {

// The nodes that may have a partner within `range`: those within range of the bounding
// sphere of an image of another capsule. Capsule pairs are tested first (their bounding
// spheres within range, over the 27 images around the nearest-cell one), then the
// nodes of each capsule against the few spheres that pass. Ascending node order.
std::vector<int> nodes_near_others(const ShearedLattice& g, int nodes_per_capsule,
                                   const std::vector<Vec3>& x, double range) {
  const int n = int(x.size()), num_capsules = n / nodes_per_capsule;
  const std::vector<Sphere> s = bounding_spheres(nodes_per_capsule, x);
  // Per capsule a: the image centres of other capsules whose spheres come within range.
  std::vector<std::vector<std::pair<Vec3, double>>> spheres(num_capsules);
  for (int a = 0; a < num_capsules; ++a)
    for (int b = 0; b < num_capsules; ++b) {
      if (a == b)
        continue;
      const Vec3 d = wrap_to_cell(g, s[b].centre - s[a].centre);
      for (int n1 = -1; n1 <= 1; ++n1)
        for (int n2 = -1; n2 <= 1; ++n2)
          for (int n3 = -1; n3 <= 1; ++n3) {
            const Vec3 image = s[a].centre + d + lattice_point(g, n1, n2, n3);
            if (norm(image - s[a].centre) <= s[a].radius + s[b].radius + range)
              spheres[a].push_back({image, s[b].radius + range});
          }
    }
  std::vector<int> near;
  for (int i = 0; i < n; ++i)
    for (const auto& [c, r] : spheres[i / nodes_per_capsule])
      if (norm(x[i] - c) <= r) {
        near.push_back(i);
        break;
      }
  return near;
}

} // namespace

void add_repulsion_gradient(const ShearedLattice& g, int nodes_per_capsule,
                            const std::vector<Vec3>& x, const RepulsionOptions& r,
                            std::vector<Vec3>& grad, std::vector<int>* repelled) {
  const int n = int(x.size()), num_capsules = n / nodes_per_capsule;
  if (repelled)
    repelled->assign(num_capsules, 0);
  // A node outside every other capsule's sphere widened by the range has no partner, nor
  // is it one: the cells hold only the others, in the same order, so each node's sum
  // meets its partners in the same order as over all nodes.
  const std::vector<int> nodes = nodes_near_others(g, nodes_per_capsule, x, r.range);
  std::vector<Vec3> points(nodes.size());
  for (size_t k = 0; k < nodes.size(); ++k)
    points[k] = x[nodes[k]];
  // A short range in a large box: far more cells than points, so they are searched.
  const PeriodicCells cells(g, r.range, points, PeriodicCells::Index::search);
  std::vector<Vec3> sum(n);
  std::vector<char> near(n, 0);
  // Each node sums the forces of its own partners: every pair is visited from both
  // sides, and the result does not depend on the thread count.
#pragma omp parallel for schedule(dynamic, 64)
  for (int k = 0; k < int(nodes.size()); ++k) {
    const int i = nodes[k], capsule = i / nodes_per_capsule;
    cells.for_neighbours(x[i], [&](int m, Vec3 image) {
      if (nodes[m] / nodes_per_capsule == capsule)
        return;
      const Vec3 d = x[i] - image;
      const double dist = norm(d);
      if (dist >= r.range || dist == 0)
        return;
      const double s = 1.0 - dist / r.range;
      sum[i] += (-r.force * s * s / dist) * d; // dE/dx_i = -force (1 - d/range)^2 d/|d|
      near[i] = 1;
    });
  }
  for (int i = 0; i < n; ++i)
    grad[i] += sum[i];
  if (repelled)
    for (int i = 0; i < n; ++i)
      (*repelled)[i / nodes_per_capsule] += near[i];
}

} // namespace capsim
