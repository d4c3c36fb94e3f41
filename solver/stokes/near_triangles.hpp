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

NearLists find_near_triangles(const std::vector<Vec3>& nodes,
                              const std::vector<Vec3>& centroids,
                              const std::vector<double>& diameters, double far_ratio);

} // namespace capsim
