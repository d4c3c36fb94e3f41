#include "dynamics/lees_edwards.hpp"

#include "mesh/surface_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

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

namespace {

// Indices of the nodes x[0..n) that lie within r of p: the only ones of a capsule that
// can come within `reach` of another whose nodes all lie within r - reach of p.
std::vector<int> nodes_within(const Vec3* x, int n, Vec3 p, double r) {
  std::vector<int> near;
  for (int i = 0; i < n; ++i)
    if (norm(x[i] - p) <= r)
      near.push_back(i);
  return near;
}

// The closest pair of nodes between capsule a and b's image shifted by `shift`, searched
// only in the lens where each capsule reaches into the other's bounding sphere.
double closest_pair(const Vec3* xa, const Vec3* xb, int nn, Vec3 centre_a, Vec3 centre_b,
                    double radius_a, double radius_b, Vec3 shift, double reach) {
  std::vector<int> ia = nodes_within(xa, nn, centre_b + shift, radius_b + reach);
  std::vector<int> ib = nodes_within(xb, nn, centre_a - shift, radius_a + reach);
  double best = 1e300;
  for (int i : ia)
    for (int j : ib)
      best = std::min(best, norm(xb[j] + shift - xa[i]));
  return best;
}

} // namespace

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
  // Pairs whose bounding spheres come within reach, with the lattice shift that brings
  // b's image nearest to a.
  std::vector<ClosestApproach> pairs;
  std::vector<Vec3> shifts;
  for (int a = 0; a < num_capsules; ++a)
    for (int b = a + 1; b < num_capsules; ++b) {
      Vec3 d = wrap_to_cell(g, centre[b] - centre[a]);
      if (norm(d) > radius[a] + radius[b] + reach)
        continue;
      pairs.push_back({1e300, a, b});
      shifts.push_back((centre[a] + d) - centre[b]);
    }
#pragma omp parallel for schedule(dynamic)
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const int a = pairs[p].capsule_a, b = pairs[p].capsule_b;
    pairs[p].distance = closest_pair(&x[a * nn], &x[b * nn], nn, centre[a], centre[b],
                                     radius[a], radius[b], shifts[p], reach);
  }
  ClosestApproach best; // the first closest pair in (a, b) order, as a serial loop finds
  for (const ClosestApproach& p : pairs)
    if (p.distance < best.distance)
      best = p;
  return best;
}

} // namespace capsim
