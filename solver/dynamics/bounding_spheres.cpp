#include "dynamics/bounding_spheres.hpp"

#include <algorithm>

namespace capsim {

std::vector<Sphere> bounding_spheres(int nodes_per_capsule, const std::vector<Vec3>& x) {
  std::vector<Sphere> spheres(x.size() / nodes_per_capsule);
  for (size_t c = 0; c < spheres.size(); ++c) {
    const Vec3* xc = &x[c * nodes_per_capsule];
    Vec3 sum;
    for (int i = 0; i < nodes_per_capsule; ++i)
      sum += xc[i];
    spheres[c].centre = (1.0 / nodes_per_capsule) * sum;
    for (int i = 0; i < nodes_per_capsule; ++i)
      spheres[c].radius = std::max(spheres[c].radius, norm(xc[i] - spheres[c].centre));
  }
  return spheres;
}

} // namespace capsim
