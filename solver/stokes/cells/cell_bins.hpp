#pragma once
// Points binned into the cells of a sheared periodic box, for the neighbour sums of the
// GPU backend (and the CPU tests of the same functions). The primary cell is cut into
// n x n x n cells in fractional coordinates, each at least `reach` wide; the images of
// all points within reach of any x then lie in the 5 x 3 x 3 cells around x's cell: one
// row or layer across the flow, and two cells along it, because each row slides by s L/n
// against its neighbours (|s| <= 1/2), so |d f1| <= 1.5 reach / L. With n >= 5 every
// (cell, lattice shift) of that stencil is a distinct image. Simpler than the CPU's
// PeriodicCells, which prunes the stencil to the cut-off sphere, but it needs no
// per-target state and no branches beyond the distance test.
#include "common/hd.hpp"
#include "stokes/cells/sheared_lattice.hpp"

#include <cmath>

namespace capsim {

struct CellBins {
  ShearedLattice g;
  int n = 0;                  // cells per direction
  const int* start = nullptr; // binned points of cell c: [start[c], start[c + 1])
};

// The most cells per direction that are each at least `reach` wide (0 if none fit).
CAPSIM_HD int bins_per_side(double L, double reach) {
  return int(std::floor(L / reach));
}
// The stencil needs at least five cells per direction.
CAPSIM_HD bool bins_usable(int n) {
  return n >= 5;
}

// Fractional coordinates of p (p = u0 a1 + u1 a2 + u2 a3).
CAPSIM_HD void fractional(const ShearedLattice& g, Vec3 p, double u[3]) {
  u[0] = (p.x - g.s * p.y) / g.L, u[1] = p.y / g.L, u[2] = p.z / g.L;
}

// The cell of p in [0, n^3), with p wrapped into the primary cell.
CAPSIM_HD int bin_of(const ShearedLattice& g, int n, Vec3 p, Vec3& wrapped) {
  double u[3], o[3];
  int c[3];
  fractional(g, p, u);
  for (int a = 0; a < 3; ++a) {
    o[a] = std::floor(u[a]);
    c[a] = int((u[a] - o[a]) * n);
    c[a] = c[a] < n ? c[a] : n - 1;
  }
  wrapped = p - lattice_point(g, o[0], o[1], o[2]);
  return (c[2] * n + c[1]) * n + c[0];
}

CAPSIM_HD int floor_div_int(int k, int n) {
  return (k >= 0 ? k : k - n + 1) / n;
}

// Calls visit(j, shift) for every binned point j in the stencil around x, where `shift`
// is the lattice vector that takes the point's wrapped position to its image there.
template <class Visit>
CAPSIM_HD void for_each_binned_neighbour(const CellBins& b, Vec3 x, Visit visit) {
  double u[3];
  fractional(b.g, x, u);
  int c[3];
  for (int a = 0; a < 3; ++a)
    c[a] = int(std::floor(u[a] * b.n)); // x's cell, not wrapped
  for (int d2 = -1; d2 <= 1; ++d2)
    for (int d1 = -1; d1 <= 1; ++d1)
      for (int d0 = -2; d0 <= 2; ++d0) {
        int k[3] = {c[0] + d0, c[1] + d1, c[2] + d2}, o[3];
        for (int a = 0; a < 3; ++a) {
          o[a] = floor_div_int(k[a], b.n);
          k[a] -= o[a] * b.n;
        }
        const Vec3 shift = lattice_point(b.g, o[0], o[1], o[2]);
        const int cell = (k[2] * b.n + k[1]) * b.n + k[0];
        for (int j = b.start[cell]; j < b.start[cell + 1]; ++j)
          visit(j, shift);
      }
}

} // namespace capsim
