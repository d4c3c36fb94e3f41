#pragma once
// Small shared helpers for the Catch2 tests.
#include "common/vec3.hpp"

#include <cmath>
#include <vector>

namespace capsim::testing {

// Observed convergence order from errors at successive refinements (h halves each time).
inline double observed_order(double coarse_error, double fine_error) {
  return std::log2(coarse_error / fine_error);
}

// Affine map x -> (sx x, sy y, sz z) followed by a rotation by `angle` about z.
inline std::vector<Vec3> stretched(const std::vector<Vec3>& x, double sx, double sy,
                                   double sz, double angle = 0) {
  std::vector<Vec3> out;
  double c = std::cos(angle), s = std::sin(angle);
  for (const auto& p : x) {
    Vec3 q{sx * p.x, sy * p.y, sz * p.z};
    out.push_back({c * q.x - s * q.y, s * q.x + c * q.y, q.z});
  }
  return out;
}

} // namespace capsim::testing
