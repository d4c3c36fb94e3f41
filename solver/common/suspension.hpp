#pragma once
// The two formulas that tie a suspension's parameters together (docs/conventions.md).
#include "common/constants.hpp"

#include <cmath>

namespace capsim {

// Side L of the cubic box that holds `capsules` capsules of radius a = 1 at volume
// fraction phi: phi = M (4/3) pi / L^3.
inline double periodic_box_side(int capsules, double phi) {
  return std::cbrt(capsules * 4.0 * kPi / (3.0 * phi));
}

// The factor 3 phi / (4 pi Ca) that turns a mean stresslet in Gs a^2 into the particle
// stress over mu gammadot (paper eqs. 4.5, 4.9, 4.10). phi = 0, the dilute limit, leaves
// phi out: the intrinsic values [mu], [N1], [N2].
inline double particle_stress_factor(double phi, double ca) {
  return 3.0 * (phi > 0 ? phi : 1.0) / (4.0 * kPi * ca);
}

} // namespace capsim
