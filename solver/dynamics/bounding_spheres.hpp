#pragma once
// A sphere around each capsule, for the searches between capsules (the contact check,
// the repulsion) that skip pairs and nodes out of each other's reach.
#include "common/vec3.hpp"

#include <vector>

namespace capsim {

struct Sphere {
  Vec3 centre;       // the mean of the capsule's nodes
  double radius = 0; // the largest distance of a node from it
};

// One sphere per capsule of x (num_capsules blocks of nodes_per_capsule nodes).
std::vector<Sphere> bounding_spheres(int nodes_per_capsule, const std::vector<Vec3>& x);

} // namespace capsim
