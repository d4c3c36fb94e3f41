#include "mesh/icosphere.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace capsim {
namespace {

Icosphere icosahedron() {
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                         {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                         {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  for (auto& x : v)
    x = (1.0 / norm(x)) * x;
  std::vector<Triangle> t = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  return {{t, static_cast<int>(v.size())}, v};
}

// One 1-to-4 subdivision; the midpoints are projected back to the unit sphere.
// Children of triangle t are stored at 4t..4t+3, which parent_triangle() relies on.
Icosphere subdivide(const Icosphere& in) {
  Icosphere out;
  out.positions = in.positions;
  std::map<std::pair<int, int>, int> midpoint;
  auto mid = [&](int a, int b) {
    auto key = std::minmax(a, b);
    auto it = midpoint.find(key);
    if (it != midpoint.end())
      return it->second;
    Vec3 m = 0.5 * (out.positions[a] + out.positions[b]);
    out.positions.push_back((1.0 / norm(m)) * m);
    int id = static_cast<int>(out.positions.size()) - 1;
    midpoint.emplace(key, id);
    return id;
  };
  for (const auto& t : in.topology.triangles) {
    int a = mid(t[0], t[1]), b = mid(t[1], t[2]), c = mid(t[2], t[0]);
    out.topology.triangles.push_back({t[0], a, c});
    out.topology.triangles.push_back({t[1], b, a});
    out.topology.triangles.push_back({t[2], c, b});
    out.topology.triangles.push_back({a, b, c});
  }
  out.topology.num_nodes = static_cast<int>(out.positions.size());
  return out;
}

} // namespace

Icosphere make_icosphere(int level) {
  if (level < kMinMeshLevel || level > kMaxMeshLevel)
    throw std::invalid_argument(
        "mesh_level must be an integer in [" + std::to_string(kMinMeshLevel) + ", " +
        std::to_string(kMaxMeshLevel) + "], got " + std::to_string(level));
  Icosphere s = icosahedron();
  for (int l = 0; l < level; ++l)
    s = subdivide(s);
  return s;
}

} // namespace capsim
