#pragma once
// Pointwise terms of the Beenakker/Hasimoto split of the periodic Stokeslet
// (paper eqs. 2.3-2.7), in the normalisation J = d/r + r r / r^3 of eq. 2.2:
//   J^E(r) = sum_images J^EI(r_n) + (8 pi / V) sum_{k != 0} J^EII(k) cos(k . r)
#include "common/fast_special.hpp"
#include "common/vec3.hpp"

#include <cmath>

namespace capsim {

constexpr double kSqrtPi = 1.77245385090551602730;

// The two radial factors of the real-space screened Stokeslet (eqs. 2.4, 2.6, 2.7),
// J^EI(r) f = a f + b r, from |r|^2 and r.f, with erfc(x) written as exp(-x^2) erfcx(x)
// through the branch-free functions of fast_special.hpp, so that loops over sources
// vectorise. T = double (1e-14 relative) or float (4e-7: ewald.real_space_precision).
template <class T>
CAPSIM_HD_INLINE void ewald_real_factors(T r2, T rf, T xi, T& a, T& b) {
  const T K = sizeof(T) == sizeof(float) ? T(kErfcxKSingle) : T(kErfcxK);
  const T rr = std::sqrt(r2), x = xi * rr, x3 = x * x * x;
  // One division for both reciprocals, 1/r and 1/(K + x).
  const T inv_both = T(1) / (rr * (K + x));
  const T rinv = (K + x) * inv_both;
  const T g = exp_nonpositive(-x * x), c = erfcx_nonnegative(x, rr * inv_both);
  const T inv_sqrt_pi = T(0.56418958354775628); // a multiply, not a division
  const T e1 = g * (c + (T(4) * x3 - T(6) * x) * inv_sqrt_pi);
  const T e2 = g * (c + (T(2) * x - T(4) * x3) * inv_sqrt_pi);
  a = e1 * rinv;
  b = e2 * rf * rinv * rinv * rinv;
}

// The real-space screened Stokeslet applied to f, in double precision.
CAPSIM_HD_INLINE Vec3 ewald_real_apply(Vec3 r, Vec3 f, double xi) {
  double a, b;
  ewald_real_factors(dot(r, r), dot(r, f), xi, a, b);
  return a * f + b * r;
}

// Reciprocal-space weight of wave vector k (eq. 2.5 without the cosine) applied to f:
// (I/k^2 - k k / k^4) (1 + k^2/(4 xi^2) + k^4/(8 xi^4)) exp(-k^2/(4 xi^2)) f.
CAPSIM_HD Vec3 ewald_recip_apply(Vec3 k, Vec3 f, double xi) {
  double k2 = dot(k, k), q = k2 / (4.0 * xi * xi);
  double w = (1.0 + q + 2.0 * q * q) * std::exp(-q) / k2;
  return w * (f - (dot(k, f) / k2) * k);
}

} // namespace capsim
