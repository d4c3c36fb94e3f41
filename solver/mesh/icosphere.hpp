#pragma once
// Capsule mesh: an icosahedron subdivided `level` times and projected to the unit sphere
// (paper section 3). Level 2 = 320 triangles / 162 nodes, 3 = 1280 / 642, 4 = 5120 /
// 2562. Connectivity (Topology) is kept apart from positions so that one topology serves
// every capsule and every deformed state.
#include "common/vec3.hpp"

#include <array>
#include <vector>

namespace capsim {

using Triangle = std::array<int, 3>; // node indices, counter-clockwise seen from outside

struct Topology {
  std::vector<Triangle> triangles;
  int num_nodes = 0;
};

struct Icosphere {
  Topology topology;
  std::vector<Vec3> positions; // on the unit sphere
};

constexpr int kMinMeshLevel = 0;
constexpr int kMaxMeshLevel = 6;

// Throws std::invalid_argument for a level outside [kMinMeshLevel, kMaxMeshLevel].
Icosphere make_icosphere(int level);

// Triangles of an icosphere of this level: 20 * 4^level (also the patch count P of the
// multipole patches of that level).
inline int icosphere_triangles(int level) {
  return 20 << (2 * level);
}

// The level of an icosphere topology, from its 20 * 4^level triangles.
inline int icosphere_level(const Topology& topo) {
  int level = 0;
  while (icosphere_triangles(level) < int(topo.triangles.size()))
    ++level;
  return level;
}

// The level-`coarse` face each fine triangle of make_icosphere(fine) descends from
// (subdivision keeps children contiguous: fine triangle t comes from t /
// 4^(fine-coarse)).
inline int parent_triangle(int fine_triangle, int fine_level, int coarse_level) {
  return fine_triangle >> (2 * (fine_level - coarse_level));
}

} // namespace capsim
