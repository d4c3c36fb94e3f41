#pragma once
// Neighbour search in a sheared periodic box: points are wrapped into the primary cell
// and binned into cells in fractional coordinates (a fraction of `reach` wide). The
// images of all points within `reach` of any x lie in the cells around x's cell that the
// sphere of radius `reach` meets: layers and rows across the flow up to floor(reach n/L)
// + 1 cells away, and along each row the cells that the sphere's chord (widened by the
// shear tilt of the row) covers. Each unwrapped cell is a distinct (cell, lattice shift)
// pair, so every image is visited once, also when the same cell is met under several
// shifts (several images, reach > L).
#include "common/vec3.hpp"
#include "stokes/cells/sheared_lattice.hpp"

#include <algorithm>
#include <vector>

namespace capsim {

class PeriodicCells {
public:
  // How a cell's points are found: a table of every cell's start (building it costs
  // O(cells), each lookup O(1)), or a search of the points' cells in cell order (O(points
  // log points) to build, O(log points) a lookup): for few points among very many cells,
  // as the repulsion's short range in a large box. The order is the same.
  enum class Index { table, search };

  // Cells 1/cells_per_reach of `reach` wide (the stencil's cells then hold about twice
  // the sphere's volume at 3, over six times it at 1; fewer cells cost less to build and
  // walk where points are sparse).
  PeriodicCells(const ShearedLattice& g, double reach, const std::vector<Vec3>& points,
                Index index = Index::table, double cells_per_reach = 3.0);

  // Calls visit(begin, end, shift) for runs [begin, end) of points in cell order
  // (`point(j)`, `wrapped(j)`) whose images wrapped(j) + shift cover the cells around x.
  // The cells along the flow direction are contiguous in that order, so one row of the
  // stencil is one or two runs: few calls, and long contiguous loops for the caller.
  template <class Visit> void for_neighbour_runs(Vec3 x, Visit visit) const {
    int c[3];
    double f[3]; // x's place inside its cell, in cell widths
    const Vec3 x_shift = wrap(x, c, f);
    const double h[3] = {g_.L / n_[0], g_.L / n_[1], g_.L / n_[2]};
    // Distance across rows (y) and layers (z) from x to the cells d away, in length.
    auto gap = [&](int d, int a) {
      return h[a] * (d > 0 ? d - f[a] : d < 0 ? f[a] - d - 1 : 0.0);
    };
    for (int d3 = -half_layers_; d3 <= half_layers_; ++d3) {
      const double dz = gap(d3, 2);
      for (int d2 = -half_rows_; d2 <= half_rows_; ++d2) {
        const double dy = gap(d2, 1), rest = reach_ * reach_ - dy * dy - dz * dz;
        if (rest < 0)
          continue;
        // Along the flow, x - y = h0 dc1 + s h1 dc2 (dc in cell widths, dc2 over the
        // row): the cells with |x - y| <= rho for some dc2 in [d2 - f1, d2 + 1 - f1].
        const double rho = std::sqrt(rest);
        const double t0 = g_.s * h[1] * (d2 - f[1]), t1 = g_.s * h[1] * (d2 + 1 - f[1]);
        const double lo = (-rho - std::max(t0, t1)) / h[0] + f[0];
        const double hi = (rho - std::min(t0, t1)) / h[0] + f[0];
        int k[3] = {0, c[1] + d2, c[2] + d3}, o[3];
        for (int a = 1; a < 3; ++a) {
          o[a] = floor_div(k[a], n_[a]);
          k[a] -= o[a] * n_[a];
        }
        const int row = (k[2] * n_[1] + k[1]) * n_[0];
        // Cells first .. last along the flow, split where they wrap around.
        for (int k1 = c[0] + int(std::floor(lo)), last = c[0] + int(std::floor(hi));
             k1 <= last;) {
          const int o1 = floor_div(k1, n_[0]), first = k1 - o1 * n_[0];
          const int end = std::min(n_[0] - 1, first + (last - k1));
          const Vec3 shift = lattice_point(g_, o1, o[1], o[2]) + x_shift;
          visit(cell_start(row + first), cell_start(row + end + 1), shift);
          k1 += end - first + 1;
        }
      }
    }
  }

  // Calls visit(point_index, image) for every point whose image lies in the cells
  // around x; the image is the one on x's side of the periodic boundaries.
  template <class Visit> void for_neighbours(Vec3 x, Visit visit) const {
    for_neighbour_runs(x, [&](int begin, int end, Vec3 shift) {
      for (int j = begin; j < end; ++j)
        visit(index_[j], wrapped_[j] + shift);
    });
  }

  // Gathers the images within sqrt(rc2) of x into buffer b (b.n: how many;
  // b.make_room(m): room for m pairs, the first b.n kept): for every candidate j in cell
  // order, put(m, j, xs) writes slot m of b from x relative to the unshifted images, xs
  // (so x - image = xs - wrapped(j)), and returns the squared separation; only those
  // within reach advance m. Branch-free compaction: every candidate is written, which
  // keeps the loop free of unpredictable branches (the pair sums then run one vectorised
  // loop over b).
  template <class Buffer, class Put>
  void gather_within(Vec3 x, double rc2, Buffer& b, Put put) const {
    b.n = 0;
    for_neighbour_runs(x, [&](int begin, int end, Vec3 shift) {
      b.make_room(b.n + size_t(end - begin));
      const Vec3 xs = x - shift;
      size_t m = b.n;
      for (int j = begin; j < end; ++j)
        m += put(m, j, xs) < rc2 ? 1 : 0;
      b.n = m;
    });
  }

  int size() const { return int(index_.size()); }
  int point(int j) const { return index_[j]; }             // the j-th point in cell order
  const Vec3& wrapped(int j) const { return wrapped_[j]; } // and its wrapped position

private:
  // Wraps p into the primary cell: returns the lattice vector removed (p - wrapped) and
  // the cell of the wrapped point.
  // (and, when `frac` is given, the place of p inside that cell, in cell widths).
  Vec3 wrap(Vec3 p, int cell[3], double* frac = nullptr) const;
  static int floor_div(int k, int n) { return (k >= 0 ? k : k - n + 1) / n; }
  // Where cell c's points begin in cell order (c = the number of cells: the end).
  int cell_start(int c) const {
    return start_.empty() ? int(std::lower_bound(cell_of_.begin(), cell_of_.end(), c) -
                                cell_of_.begin())
                          : start_[c];
  }

  ShearedLattice g_;
  double reach_;
  int n_[3];                       // cells per direction
  int half_rows_, half_layers_;    // rows (y) and layers (z) of cells within reach
  std::vector<Vec3> wrapped_;      // wrapped points in cell order
  std::vector<int> start_, index_; // cell c holds index_[start_[c] .. start_[c + 1])
  std::vector<int> cell_of_;       // Index::search: the cell of each point in cell order
};

} // namespace capsim
