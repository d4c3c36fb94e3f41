#include "stokes/quadrature/near_triangles.hpp"

#include <algorithm>
#include <cmath>

namespace capsim {
namespace {

int clampi(int v, int lo, int hi) {
  return std::max(lo, std::min(hi, v));
}

// Triangles `ids` binned by centroid in cells of side `reach` over the box [lo, hi] of
// the nodes: a node's triangles within reach lie in its own and the 26 neighbouring
// cells. Centroids outside the box are clamped into the boundary cells, which only makes
// those cells hold more candidates, never miss one.
class CentroidBins {
public:
  CentroidBins(Vec3 lo, Vec3 hi, double reach, const std::vector<Vec3>& centroids,
               const std::vector<int>& ids)
      : lo_(lo), reach_(reach) {
    const double ext[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
    for (int a = 0; a < 3; ++a)
      n_[a] = std::max(1, std::min(256, int(ext[a] / reach) + 1));
    bins_.resize(size_t(n_[0]) * n_[1] * n_[2]);
    for (int t : ids) {
      int c[3];
      cell_of(centroids[t], c);
      bins_[index(c[0], c[1], c[2])].push_back(t);
    }
  }

  template <class Visit> void for_candidates(Vec3 p, Visit visit) const {
    int c[3];
    cell_of(p, c);
    for (int z = std::max(0, c[2] - 1); z <= std::min(n_[2] - 1, c[2] + 1); ++z)
      for (int y = std::max(0, c[1] - 1); y <= std::min(n_[1] - 1, c[1] + 1); ++y)
        for (int x = std::max(0, c[0] - 1); x <= std::min(n_[0] - 1, c[0] + 1); ++x)
          for (int t : bins_[index(x, y, z)])
            visit(t);
  }

private:
  void cell_of(Vec3 p, int c[3]) const {
    const double r[3] = {p.x - lo_.x, p.y - lo_.y, p.z - lo_.z};
    for (int a = 0; a < 3; ++a)
      c[a] = clampi(int(std::floor(r[a] / reach_)), 0, n_[a] - 1);
  }
  size_t index(int x, int y, int z) const { return (size_t(z) * n_[1] + y) * n_[0] + x; }

  Vec3 lo_;
  double reach_;
  int n_[3];
  std::vector<std::vector<int>> bins_;
};

} // namespace

DiameterGroups split_by_diameter(const std::vector<double>& diameters, double far_ratio) {
  double mean = 0, largest = 0;
  for (double d : diameters)
    mean += d / double(diameters.size()), largest = std::max(largest, d);
  const double split = std::min(largest, 2.0 * mean);
  DiameterGroups g;
  for (int t = 0; t < int(diameters.size()); ++t)
    g.ids[diameters[t] > split].push_back(t);
  g.reach[0] = far_ratio * split;
  g.reach[1] = far_ratio * largest;
  return g;
}

NearLists find_near_triangles(const std::vector<Vec3>& nodes,
                              const std::vector<Vec3>& centroids,
                              const std::vector<double>& diameters, double far_ratio) {
  Vec3 lo = nodes.front(), hi = nodes.front();
  for (const auto& p : nodes) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const DiameterGroups split = split_by_diameter(diameters, far_ratio);
  std::vector<CentroidBins> groups;
  for (int big = 0; big < 2; ++big)
    if (!split.ids[big].empty())
      groups.emplace_back(lo, hi, split.reach[big], centroids, split.ids[big]);
  NearLists out;
  out.offset.assign(nodes.size() + 1, 0);
  for (size_t i = 0; i < nodes.size(); ++i) {
    for (const CentroidBins& bins : groups)
      bins.for_candidates(nodes[i], [&](int t) {
        if (norm(nodes[i] - centroids[t]) < far_ratio * diameters[t])
          out.triangle.push_back(t);
      });
    out.offset[i + 1] = int(out.triangle.size());
  }
  return out;
}

} // namespace capsim
