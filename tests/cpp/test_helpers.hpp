#pragma once
// Small shared helpers for the Catch2 tests.
#include "common/vec3.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace capsim::testing {

// Observed convergence order from errors at successive refinements (h halves each time).
inline double observed_order(double coarse_error, double fine_error) {
  return std::log2(coarse_error / fine_error);
}

// The largest |a_i - b_i| over the largest |b_i|: the relative difference of two fields
// at the same nodes.
inline double relative_difference(const std::vector<Vec3>& a,
                                  const std::vector<Vec3>& b) {
  double d = 0, s = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, norm(a[i] - b[i]));
    s = std::max(s, norm(b[i]));
  }
  return d / s;
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

// x with every coordinate moved by a uniform random amount in [-amplitude, amplitude].
inline std::vector<Vec3> perturbed(const std::vector<Vec3>& x, double amplitude,
                                   unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  std::vector<Vec3> out = x;
  for (auto& p : out)
    p += Vec3{u(rng), u(rng), u(rng)};
  return out;
}

// Checks grad against central differences of energy(positions) at every stride-th node:
// returns {largest difference, largest finite difference}.
template <class Energy>
std::pair<double, double> gradient_check(Energy energy, const std::vector<Vec3>& x,
                                         const std::vector<Vec3>& grad, int stride) {
  const double h = 1e-6;
  double worst = 0, scale = 0;
  for (size_t i = 0; i < x.size(); i += stride)
    for (int a = 0; a < 3; ++a) {
      auto xp = x, xm = x;
      (&xp[i].x)[a] += h;
      (&xm[i].x)[a] -= h;
      const double fd = (energy(xp.data()) - energy(xm.data())) / (2 * h);
      worst = std::max(worst, std::abs(fd - (&grad[i].x)[a]));
      scale = std::max(scale, std::abs(fd));
    }
  return {worst, scale};
}

} // namespace capsim::testing
