#pragma once
// Pointwise terms of the Ewald split of the stresslet T_ijk(r) = -6 r_i r_j r_k / |r|^5
// (double_layer.hpp), Hasimoto's splitting (Hasimoto 1959; for the stresslet: af
// Klinteberg & Tornberg 2014, "Fast Ewald summation for Stokesian particle suspensions",
// Int. J. Numer. Meth. Fluids 76, 669, section 2), derived here as follows.
//
// With the stokeslet G = (I lap - grad grad) |r| (the J of ewald_kernel.hpp) and its
// pressure p = -grad lap |r|, the stresslet T_ijk = -d_ik p_j + d_k G_ij + d_i G_kj is
//   T_ijk = (d_ik d_j + d_ij d_k + d_jk d_i) lap f - 2 d_i d_j d_k f,   f = |r|,   (1)
// a fully symmetric tensor. Its Fourier transform (f^ = -8 pi / k^4, d -> i k) is
//   T^_ijk(k) = 8 pi i [ (d_ik k_j + d_ij k_k + d_jk k_i) / k^2 - 2 k_i k_j k_k / k^4 ].
// Hasimoto screens f^ by phi(k) = (1 + k^2/(4 xi^2)) exp(-k^2/(4 xi^2)) (the stokeslet
// then splits into Hasimoto's pair); applying (1) to both parts splits T exactly:
//  - Fourier part: T^F^(k) = phi(k) T^(k);
//  - real part: f^R with f^R' = erfc(xi r) (lap f^F = 2 erf(xi r)/r + 2 xi/sqrt(pi)
//    exp(-xi^2 r^2), integrated once), and (1) for a radial f gives
//      T^R_ijk(r) = C(r) (d_ij r_k + d_jk r_i + d_ik r_j) + E(r) r_i r_j r_k,
//      C = 4 xi^3/sqrt(pi) exp(-xi^2 r^2),
//      E = -2/r^4 [3 erfc(xi r)/r + 2 xi/sqrt(pi) (3 + 2 xi^2 r^2) exp(-xi^2 r^2)],  (2)
//    which tends to T as xi -> 0.
// The periodic stresslet of a lattice of cell volume V (Poisson summation):
//   T^per(r) = sum_images T^R(r_n) + (1/V) sum_{k != 0} T^F^(k) exp(i k . r)
//            = sum_images T^R(r_n) - (8 pi / V) sum_{k != 0} phi(k) A(k) sin(k . r),  (3)
//   A_ijk(k) = (d_ik k_j + d_ij k_k + d_jk k_i) / k^2 - 2 k_i k_j k_k / k^4,
// the cosines cancelling between k and -k (A is odd). The k = 0 term is zero: see
// periodic_double_layer.hpp.
#include "common/constants.hpp"
#include "common/fast_special.hpp"
#include "common/hd.hpp"
#include "common/vec3.hpp"

#include <cmath>

namespace capsim {

// The symmetric rank-3 tensor c (d_ij v_k + d_jk v_i + d_ik v_j) + e v_i v_j v_k
// contracted with u_i and a_k: c [(u.a) v + (v.a) u + (u.v) a] + e (u.v)(a.v) v. Both
// parts of the split have this form: (2) with v = r, (3) with v = k, c = 1/k^2,
// e = -2/k^4.
CAPSIM_HD Vec3 symmetric_rank3_apply(Vec3 v, double c, double e, Vec3 u, Vec3 a) {
  const double uv = dot(u, v), av = dot(a, v);
  return c * (dot(u, a) * v + av * u + uv * a) + (e * uv * av) * v;
}

// The same tensor contracted with a_k alone, a symmetric 3 x 3 matrix, added to m (xx,
// yy, zz, xy, xz, yz): c (a_i v_j + v_i a_j + d_ij (v.a)) + e (v.a) v_i v_j.
CAPSIM_HD void symmetric_rank3_add_matrix(Vec3 v, double c, double e, Vec3 a,
                                          double m[6]) {
  const double av = dot(a, v), s = e * av;
  m[0] += c * (2.0 * a.x * v.x + av) + s * v.x * v.x;
  m[1] += c * (2.0 * a.y * v.y + av) + s * v.y * v.y;
  m[2] += c * (2.0 * a.z * v.z + av) + s * v.z * v.z;
  m[3] += c * (a.x * v.y + v.x * a.y) + s * v.x * v.y;
  m[4] += c * (a.x * v.z + v.x * a.z) + s * v.x * v.z;
  m[5] += c * (a.y * v.z + v.y * a.z) + s * v.y * v.z;
}

// The symmetric part of u a^T, (u a^T + a u^T)/2 (xx, yy, zz, xy, xz, yz): all that a
// fully symmetric rank-3 tensor sees of u_i and a_k.
CAPSIM_HD void symmetric_product(Vec3 u, Vec3 a, double d[6]) {
  d[0] = u.x * a.x, d[1] = u.y * a.y, d[2] = u.z * a.z;
  d[3] = 0.5 * (u.x * a.y + u.y * a.x);
  d[4] = 0.5 * (u.x * a.z + u.z * a.x);
  d[5] = 0.5 * (u.y * a.z + u.z * a.y);
}

// The symmetric matrix m (xx, yy, zz, xy, xz, yz) times u.
CAPSIM_HD Vec3 symmetric_matrix_apply(const double m[6], Vec3 u) {
  return {m[0] * u.x + m[3] * u.y + m[4] * u.z, m[3] * u.x + m[1] * u.y + m[5] * u.z,
          m[4] * u.x + m[5] * u.y + m[2] * u.z};
}

// The radial factors C and E of the real-space stresslet (2), from |r|^2, with erfc(x)
// written as exp(-x^2) erfcx(x) through the branch-free functions of fast_special.hpp
// (as ewald_real_factors), so that loops over sources vectorise (stresslet_real_sum).
CAPSIM_HD_INLINE void stresslet_real_factors(double r2, double xi, double& c, double& e) {
  constexpr double kInvSqrtPi = 0.56418958354775628695;
  const double r = std::sqrt(r2), x = xi * r;
  // One division for both reciprocals, 1/r and 1/(K + x).
  const double inv_both = 1.0 / (r * (kErfcxK + x));
  const double rinv = (kErfcxK + x) * inv_both, rinv2 = rinv * rinv;
  const double g = exp_nonpositive(-x * x), erfcx = erfcx_nonnegative(x, r * inv_both);
  c = 4.0 * kInvSqrtPi * xi * xi * xi * g;
  e = -2.0 * g * rinv2 * rinv2 *
      (3.0 * erfcx * rinv + 2.0 * kInvSqrtPi * xi * (3.0 + 2.0 * x * x));
}

// u_i T^R_ijk(r) a_k (2) from the symmetric part d = (u a^T + a u^T)/2 (xx, yy, zz, xy,
// xz, yz), which is all the fully symmetric T sees:
// C [tr(d) r + 2 d r] + E (r . d r) r.
CAPSIM_HD_INLINE Vec3 stresslet_real_apply_symmetric(Vec3 r, const double d[6],
                                                     double xi) {
  double c, e;
  stresslet_real_factors(dot(r, r), xi, c, e);
  const Vec3 dr = symmetric_matrix_apply(d, r);
  return c * ((d[0] + d[1] + d[2]) * r + 2.0 * dr) + (e * dot(r, dr)) * r;
}

// T^R_ijk(r) a_k (2), added to m.
CAPSIM_HD void stresslet_real_add_matrix(Vec3 r, Vec3 a, double xi, double m[6]) {
  double c, e;
  stresslet_real_factors(dot(r, r), xi, c, e);
  symmetric_rank3_add_matrix(r, c, e, a, m);
}

// Hasimoto's screening phi(k) = (1 + q) exp(-q), q = k^2/(4 xi^2).
CAPSIM_HD double stresslet_fourier_screening(double k2, double xi) {
  const double q = k2 / (4.0 * xi * xi);
  return (1.0 + q) * std::exp(-q);
}

// u_i A_ijk(k) a_k of (3), without phi.
CAPSIM_HD Vec3 stresslet_fourier_apply(Vec3 k, Vec3 u, Vec3 a) {
  const double k2 = dot(k, k);
  return symmetric_rank3_apply(k, 1.0 / k2, -2.0 / (k2 * k2), u, a);
}

// A_ijk(k) b_k of (3), without phi, added to m.
CAPSIM_HD void stresslet_fourier_add_matrix(Vec3 k, Vec3 b, double m[6]) {
  const double k2 = dot(k, k);
  symmetric_rank3_add_matrix(k, 1.0 / k2, -2.0 / (k2 * k2), b, m);
}

} // namespace capsim
