#include "dynamics/lees_edwards.hpp"

#include "mesh/surface_geometry.hpp"

#include <cmath>

namespace capsim {

int remap_capsules(const Topology& topo, int num_capsules, const ShearedLattice& g,
                   std::vector<Vec3>& x) {
  const int nn = topo.num_nodes;
  int moved = 0;
  for (int c = 0; c < num_capsules; ++c) {
    Vec3* xc = &x[c * nn];
    Vec3 centre = volume_centroid(topo, xc);
    double f2 = centre.y / g.L, f3 = centre.z / g.L,
           f1 = (centre.x - g.s * centre.y) / g.L;
    Vec3 shift = lattice_point(g, -std::floor(f1), -std::floor(f2), -std::floor(f3));
    if (dot(shift, shift) == 0)
      continue;
    for (int i = 0; i < nn; ++i)
      xc[i] += shift;
    ++moved;
  }
  return moved;
}

ClosestApproach closest_approach(const Topology& topo, int num_capsules,
                                 const ShearedLattice& g, const std::vector<Vec3>& x,
                                 double reach) {
  const int nn = topo.num_nodes;
  std::vector<Vec3> centre(num_capsules);
  std::vector<double> radius(num_capsules, 0.0);
  for (int c = 0; c < num_capsules; ++c) {
    centre[c] = volume_centroid(topo, &x[c * nn]);
    for (int i = 0; i < nn; ++i)
      radius[c] = std::max(radius[c], norm(x[c * nn + i] - centre[c]));
  }
  ClosestApproach best;
  for (int a = 0; a < num_capsules; ++a)
    for (int b = a + 1; b < num_capsules; ++b) {
      // The image of b nearest to a, as a lattice shift applied to b's nodes.
      Vec3 d = wrap_to_cell(g, centre[b] - centre[a]);
      if (norm(d) > radius[a] + radius[b] + reach)
        continue;
      Vec3 shift = (centre[a] + d) - centre[b];
      for (int i = 0; i < nn; ++i)
        for (int j = 0; j < nn; ++j) {
          double dist = norm(x[b * nn + j] + shift - x[a * nn + i]);
          if (dist < best.distance)
            best = {dist, a, b};
        }
    }
  return best;
}

} // namespace capsim
