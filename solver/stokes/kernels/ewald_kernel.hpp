#pragma once
// Pointwise terms of the Beenakker/Hasimoto split of the periodic Stokeslet
// (paper eqs. 2.3-2.7), in the normalisation J = d/r + r r / r^3 of eq. 2.2:
//   J^E(r) = sum_images J^EI(r_n) + (8 pi / V) sum_{k != 0} J^EII(k) cos(k . r)
#include "common/fast_special.hpp"
#include "common/vec3.hpp"

#include <cmath>

namespace capsim {

constexpr double kSqrtPi = 1.77245385090551602730;

// Real-space screened Stokeslet applied to f (eqs. 2.4, 2.6, 2.7), with erfc(x) written
// as exp(-x^2) erfcx(x) through the branch-free functions of fast_special.hpp, so that
// loops over sources vectorise.
CAPSIM_HD_INLINE Vec3 ewald_real_apply(Vec3 r, Vec3 f, double xi) {
  const double rr = std::sqrt(dot(r, r)), x = xi * rr, x3 = x * x * x;
  // One division for both reciprocals, 1/r and 1/(K + x).
  const double inv_both = 1.0 / (rr * (kErfcxK + x));
  const double rinv = (kErfcxK + x) * inv_both;
  const double g = exp_nonpositive(-x * x), c = erfcx_nonnegative(x, rr * inv_both);
  constexpr double inv_sqrt_pi = 0.56418958354775628; // a multiply, not a division
  const double e1 = g * (c + (4.0 * x3 - 6.0 * x) * inv_sqrt_pi);
  const double e2 = g * (c + (2.0 * x - 4.0 * x3) * inv_sqrt_pi);
  return (e1 * rinv) * f + (e2 * dot(r, f) * rinv * rinv * rinv) * r;
}

// Reciprocal-space weight of wave vector k (eq. 2.5 without the cosine) applied to f:
// (I/k^2 - k k / k^4) (1 + k^2/(4 xi^2) + k^4/(8 xi^4)) exp(-k^2/(4 xi^2)) f.
CAPSIM_HD Vec3 ewald_recip_apply(Vec3 k, Vec3 f, double xi) {
  double k2 = dot(k, k), q = k2 / (4.0 * xi * xi);
  double w = (1.0 + q + 2.0 * q * q) * std::exp(-q) / k2;
  return w * (f - (dot(k, f) / k2) * k);
}

} // namespace capsim
