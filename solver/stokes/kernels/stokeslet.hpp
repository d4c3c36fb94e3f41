#pragma once
// Free-space Stokeslet in the normalisation of paper eq. 2.2: J_ij(r) = d_ij / r + r_i
// r_j / r^3, so that a point force f on the fluid at y gives v(x) = J(x - y) f / (8 pi
// mu).
#include "common/constants.hpp"
#include "common/vec3.hpp"

namespace capsim {

// J(r) . f
CAPSIM_HD Vec3 stokeslet_apply(Vec3 r, Vec3 f) {
  double rinv = 1.0 / std::sqrt(dot(r, r));
  double rf = dot(r, f) * rinv * rinv * rinv;
  return rinv * f + rf * r;
}

// First-moment (force-dipole) term of the Stokeslet expansion (paper eqs. 3.3-3.8):
// for a load distribution with first moment D_jk = int q_j (y - c)_k dA about c,
// J(x - y) q = J(r) q - d_k J(r) D_.k + ..., r = x - c. Returned: sum_jk d_k J_ij(r) D_jk
//   = [D^T r - D r + r tr D] / r^3 - 3 r (r . D r) / r^5.
// Its antisymmetric part is the paper's rotlet R^E L, its symmetric traceless part the
// stresslet K^E S; the trace part cancels (incompressibility) and is kept for exactness.
CAPSIM_HD Vec3 stokeslet_gradient_contract(Vec3 r, const Mat3& d) {
  double r2 = dot(r, r), rinv = 1.0 / std::sqrt(r2), rinv3 = rinv * rinv * rinv;
  const double(*m)[3] = d.m;
  Vec3 dr{m[0][0] * r.x + m[0][1] * r.y + m[0][2] * r.z,
          m[1][0] * r.x + m[1][1] * r.y + m[1][2] * r.z,
          m[2][0] * r.x + m[2][1] * r.y + m[2][2] * r.z};
  Vec3 dtr{m[0][0] * r.x + m[1][0] * r.y + m[2][0] * r.z,
           m[0][1] * r.x + m[1][1] * r.y + m[2][1] * r.z,
           m[0][2] * r.x + m[1][2] * r.y + m[2][2] * r.z};
  double trace = m[0][0] + m[1][1] + m[2][2], rdr = dot(r, dr);
  return rinv3 * (dtr - dr + trace * r) - (3.0 * rdr * rinv3 / r2) * r;
}

} // namespace capsim
