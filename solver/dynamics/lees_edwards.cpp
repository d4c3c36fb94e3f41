#include "dynamics/lees_edwards.hpp"

#include "dynamics/bounding_spheres.hpp"
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
double closest_pair(const Vec3* xa, const Vec3* xb, int nn, const Sphere& a,
                    const Sphere& b, Vec3 shift, double reach) {
  std::vector<int> ia = nodes_within(xa, nn, b.centre + shift, b.radius + reach);
  std::vector<int> ib = nodes_within(xb, nn, a.centre - shift, a.radius + reach);
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
  const std::vector<Sphere> s = bounding_spheres(nn, x);
  double largest = 0;
  for (const Sphere& sphere : s)
    largest = std::max(largest, sphere.radius);
  // Every image of b (b = a: a's own, but a itself) whose bounding sphere comes within
  // reach of a's, with its lattice shift. Not only the nearest: where the box is not
  // much larger than the capsules (M = 8 at phi 0.3: L = 4.8), b may reach a from two
  // sides. An image within R of a lies within |n1| <= 1.5 R / L + 1/2 and |n2|, |n3| <=
  // R / L + 1/2 cells of the nearest (the sheared cell's x extends by |s| <= 1/2 of y).
  const double R = 2 * largest + reach;
  const int k1 = int(std::ceil(1.5 * R / g.L + 0.5)), k23 = int(std::ceil(R / g.L + 0.5));
  std::vector<ClosestApproach> pairs;
  std::vector<Vec3> shifts;
  for (int a = 0; a < num_capsules; ++a)
    for (int b = a; b < num_capsules; ++b) {
      const Vec3 nearest = wrap_to_cell(g, s[b].centre - s[a].centre);
      for (int n1 = -k1; n1 <= k1; ++n1)
        for (int n2 = -k23; n2 <= k23; ++n2)
          for (int n3 = -k23; n3 <= k23; ++n3) {
            const Vec3 d = nearest + lattice_point(g, n1, n2, n3);
            if ((a == b && n1 == 0 && n2 == 0 && n3 == 0) ||
                norm(d) > s[a].radius + s[b].radius + reach)
              continue;
            pairs.push_back({1e300, a, b});
            shifts.push_back((s[a].centre + d) - s[b].centre);
          }
    }
#pragma omp parallel for schedule(dynamic)
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const int a = pairs[p].capsule_a, b = pairs[p].capsule_b;
    pairs[p].distance =
        closest_pair(&x[a * nn], &x[b * nn], nn, s[a], s[b], shifts[p], reach);
  }
  ClosestApproach best; // the first closest pair in (a, b) order, as a serial loop finds
  for (const ClosestApproach& p : pairs)
    if (p.distance < best.distance)
      best = p;
  return best;
}

} // namespace capsim
