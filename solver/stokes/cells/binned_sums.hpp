#pragma once
// The periodic real-space sums of one target over binned sources (cell_bins.hpp): the
// screened far sum and the near-field corrections. Host-device: the GPU backend runs one
// target per thread, and the CPU tests check them against the CPU path's sums.
#include "stokes/cells/cell_bins.hpp"
#include "stokes/kernels/ewald_kernel.hpp"
#include "stokes/quadrature/near_corrections.hpp"

namespace capsim {

// sum_j J^EI(x - y_j - shift) f_j over the images within r_cut of the binned point
// sources (ys: wrapped positions, fs: forces, both in bin order); the bins must be at
// least r_cut wide.
CAPSIM_HD Vec3 binned_screened_sum(const CellBins& b, const Vec3* ys, const Vec3* fs,
                                   double xi, double r_cut, Vec3 x) {
  Vec3 sum;
  const double rc2 = r_cut * r_cut;
  for_each_binned_neighbour(b, x, [&](int j, Vec3 shift) {
    const Vec3 r = x - (ys[j] + shift);
    if (dot(r, r) < rc2)
      sum += ewald_real_apply(r, fs[j], xi);
  });
  return sum;
}

// The near corrections at x of the triangle images near it (closer than far_ratio of
// their diameters). Binned entry j is triangle tri[j] with its centroid wrapped to wc[j];
// the bins must be at least far_ratio times the largest diameter wide. own_vertex(e) is
// x's vertex (0-2) in triangle e, or -1.
template <class OwnVertex>
CAPSIM_HD Vec3 binned_near_corrections(const CellBins& b, const int* tri, const Vec3* wc,
                                       const TriangleLoad* loads, const NearRule& r,
                                       Vec3 x, OwnVertex own_vertex) {
  Vec3 sum;
  for_each_binned_neighbour(b, x, [&](int j, Vec3 shift) {
    const TriangleLoad& load = loads[tri[j]];
    const Vec3 image = wc[j] + shift;
    if (norm(x - image) >= r.far_ratio * triangle_diameter(load.p))
      return;
    Vec3 lattice = image - triangle_centroid(load.p); // a lattice vector, up to round-off
    if (norm(lattice) < 1e-9 * b.g.L)
      lattice = Vec3{};
    sum += image_near_correction(x, own_vertex(tri[j]), load, lattice, r);
  });
  return sum;
}

} // namespace capsim
