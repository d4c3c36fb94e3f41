#pragma once
// Free-space Stokeslet in the normalisation of paper eq. 2.2: J_ij(r) = d_ij / r + r_i
// r_j / r^3, so that a point force f on the fluid at y gives v(x) = J(x - y) f / (8 pi
// mu).
#include "common/vec3.hpp"

namespace capsim {

constexpr double kPi = 3.14159265358979323846;

// J(r) . f
CAPSIM_HD Vec3 stokeslet_apply(Vec3 r, Vec3 f) {
  double rinv = 1.0 / std::sqrt(dot(r, r));
  double rf = dot(r, f) * rinv * rinv * rinv;
  return rinv * f + rf * r;
}

} // namespace capsim
