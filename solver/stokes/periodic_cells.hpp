#pragma once
// Neighbour search in a sheared periodic box: points are wrapped into the primary cell
// and binned into cells in fractional coordinates (about a third of `reach` wide). The
// images of all points within `reach` of any x lie in a stencil of cells around x's cell,
// half widths floor(1.5 reach n/L) + 1 along the flow (the shear tilts the cell by |s| <=
// 1/2) and floor(reach n/L) + 1 across it. Each unwrapped cell of the stencil is a
// distinct (cell, lattice shift) pair, so every image is visited once, also when the
// stencil meets the same cell under several shifts (several images, reach > L).
#include "common/vec3.hpp"
#include "stokes/sheared_lattice.hpp"

#include <vector>

namespace capsim {

class PeriodicCells {
public:
  PeriodicCells(const ShearedLattice& g, double reach, const std::vector<Vec3>& points);

  // Calls visit(point_index, image) for every point whose image `image` lies in the cells
  // around x; the image is the one on x's side of the periodic boundaries.
  template <class Visit> void for_neighbours(Vec3 x, Visit visit) const {
    int c[3];
    Vec3 x_shift = wrap(x, c);
    for (int d3 = -w_[2]; d3 <= w_[2]; ++d3)
      for (int d2 = -w_[1]; d2 <= w_[1]; ++d2)
        for (int d1 = -w_[0]; d1 <= w_[0]; ++d1) {
          int k[3] = {c[0] + d1, c[1] + d2, c[2] + d3}, o[3];
          for (int a = 0; a < 3; ++a) { // floor division: k = o n + (k mod n)
            o[a] = (k[a] >= 0 ? k[a] : k[a] - n_[a] + 1) / n_[a];
            k[a] -= o[a] * n_[a];
          }
          const Vec3 shift = lattice_point(g_, o[0], o[1], o[2]) + x_shift;
          const int cell = (k[2] * n_[1] + k[1]) * n_[0] + k[0];
          for (int j = start_[cell]; j < start_[cell + 1]; ++j)
            visit(index_[j], wrapped_[index_[j]] + shift);
        }
  }

private:
  // Wraps p into the primary cell: returns the lattice vector removed (p - wrapped) and
  // the cell of the wrapped point.
  Vec3 wrap(Vec3 p, int cell[3]) const;

  ShearedLattice g_;
  int n_[3]; // cells per direction
  int w_[3]; // stencil half-widths
  std::vector<Vec3> wrapped_;
  std::vector<int> start_, index_;
};

} // namespace capsim
