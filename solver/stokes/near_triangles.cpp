#include "stokes/near_triangles.hpp"

#include <algorithm>
#include <cmath>

namespace capsim {
namespace {

int clampi(int v, int lo, int hi) {
  return std::max(lo, std::min(hi, v));
}

} // namespace

NearLists find_near_triangles(const std::vector<Vec3>& nodes,
                              const std::vector<Vec3>& centroids,
                              const std::vector<double>& diameters, double far_ratio) {
  double reach = 0;
  Vec3 lo = nodes.front(), hi = nodes.front();
  for (double d : diameters)
    reach = std::max(reach, far_ratio * d);
  for (const auto& p : nodes) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  // Cells of side `reach`: a node's near triangles lie in its own and the 26 neighbouring
  // cells. Centroids outside the node box are clamped into the boundary cells, which only
  // makes those cells hold more candidates, never miss one.
  int n[3];
  double ext[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
  for (int a = 0; a < 3; ++a)
    n[a] = std::max(1, std::min(256, int(ext[a] / reach) + 1));
  auto cell_of = [&](Vec3 p, int c[3]) {
    double r[3] = {p.x - lo.x, p.y - lo.y, p.z - lo.z};
    for (int a = 0; a < 3; ++a)
      c[a] = clampi(int(std::floor(r[a] / reach)), 0, n[a] - 1);
  };
  std::vector<std::vector<int>> bins(size_t(n[0]) * n[1] * n[2]);
  for (size_t t = 0; t < centroids.size(); ++t) {
    int c[3];
    cell_of(centroids[t], c);
    bins[(size_t(c[2]) * n[1] + c[1]) * n[0] + c[0]].push_back(int(t));
  }
  NearLists out;
  out.offset.assign(nodes.size() + 1, 0);
  for (size_t i = 0; i < nodes.size(); ++i) {
    int c[3];
    cell_of(nodes[i], c);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
          if (x < 0 || y < 0 || z < 0 || x >= n[0] || y >= n[1] || z >= n[2])
            continue;
          for (int t : bins[(size_t(z) * n[1] + y) * n[0] + x])
            if (norm(nodes[i] - centroids[t]) < far_ratio * diameters[t])
              out.triangle.push_back(t);
        }
    out.offset[i + 1] = int(out.triangle.size());
  }
  return out;
}

} // namespace capsim
