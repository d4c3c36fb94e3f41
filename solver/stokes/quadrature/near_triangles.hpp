#pragma once
// For each node, the triangles (of all capsules) whose centroid is closer than
// far_ratio times the triangle's diameter: the set that needs accurate quadrature.
// A uniform cell grid over the triangle centroids keeps this O(N).
#include "common/vec3.hpp"

#include <vector>

namespace capsim {

struct NearLists {
  std::vector<int> offset;   // node i's triangles are index[offset[i] .. offset[i+1])
  std::vector<int> triangle; // global triangle index (capsule * T + local)
};

// A near search must reach far_ratio times each triangle's diameter. One reach for all,
// set by the largest triangle, fails when a capsule is stretched into a thread (phi 0.4,
// Ca 0.6): its few long triangles made every node scan most of the box (85 % of a step).
// So triangles more than twice the mean diameter form a group of their own with their
// longer reach; the others get a reach set by the mean. Used by the free-space search
// below and the periodic one (near_triangle_cells.hpp).
struct DiameterGroups {
  std::vector<int> ids[2]; // 0: the others, 1: triangles over twice the mean diameter
  double reach[2] = {};    // far_ratio times the largest diameter a group may hold
};
DiameterGroups split_by_diameter(const std::vector<double>& diameters, double far_ratio);

NearLists find_near_triangles(const std::vector<Vec3>& nodes,
                              const std::vector<Vec3>& centroids,
                              const std::vector<double>& diameters, double far_ratio);

} // namespace capsim
