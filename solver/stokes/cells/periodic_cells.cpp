#include "stokes/cells/periodic_cells.hpp"

#include <algorithm>
#include <cmath>

namespace capsim {

PeriodicCells::PeriodicCells(const ShearedLattice& g, double reach,
                             const std::vector<Vec3>& points, Index index,
                             double cells_per_reach)
    : g_(g), reach_(reach) {
  for (int a = 0; a < 3; ++a)
    n_[a] = std::max(1, std::min(128, int(cells_per_reach * g.L / reach)));
  // |du2|, |du3| <= reach/L for images within reach.
  half_rows_ = int(std::floor(reach * n_[1] / g.L)) + 1;
  half_layers_ = int(std::floor(reach * n_[2] / g.L)) + 1;
  const int cells = n_[0] * n_[1] * n_[2];
  std::vector<int> cell_of(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    int c[3];
    wrap(points[i], c);
    cell_of[i] = (c[2] * n_[1] + c[1]) * n_[0] + c[0];
  }
  // Cell order: by cell, and within a cell by index (a stable counting sort).
  index_.resize(points.size());
  if (index == Index::search) {
    for (size_t i = 0; i < points.size(); ++i)
      index_[i] = int(i);
    std::stable_sort(index_.begin(), index_.end(),
                     [&](int a, int b) { return cell_of[a] < cell_of[b]; });
    cell_of_.resize(points.size());
    for (size_t j = 0; j < points.size(); ++j)
      cell_of_[j] = cell_of[index_[j]];
  } else {
    std::vector<int> count(cells + 1, 0);
    for (int c : cell_of)
      ++count[c + 1];
    start_.assign(cells + 1, 0);
    for (int k = 0; k < cells; ++k)
      start_[k + 1] = start_[k] + count[k + 1];
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < points.size(); ++i)
      index_[fill[cell_of[i]]++] = int(i);
  }
  wrapped_.resize(points.size());
  for (size_t j = 0; j < points.size(); ++j) {
    int c[3];
    wrapped_[j] = points[index_[j]] - wrap(points[index_[j]], c);
  }
}

Vec3 PeriodicCells::wrap(Vec3 p, int cell[3], double* frac) const {
  const double u2 = p.y / g_.L, u3 = p.z / g_.L, u1 = (p.x - g_.s * p.y) / g_.L;
  const double f[3] = {std::floor(u1), std::floor(u2), std::floor(u3)};
  const double u[3] = {u1 - f[0], u2 - f[1], u3 - f[2]};
  for (int a = 0; a < 3; ++a) {
    cell[a] = std::min(n_[a] - 1, int(u[a] * n_[a]));
    if (frac)
      frac[a] = u[a] * n_[a] - cell[a];
  }
  return lattice_point(g_, f[0], f[1], f[2]);
}

} // namespace capsim
