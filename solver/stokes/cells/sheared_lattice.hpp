#pragma once
// The sheared (Lees-Edwards) periodic lattice (docs/conventions.md): lattice vectors
// a1 = L e_x, a2 = L (e_y + s e_x), a3 = L e_z, with the strain offset s = gammadot t
// wrapped into [-1/2, 1/2) (s and s + 1 give the same lattice); reciprocal vectors
// b1 = (2 pi / L)(1, -s, 0), b2 = (2 pi / L) e_y, b3 = (2 pi / L) e_z, so a_i . b_j = 2
// pi d_ij.
#include "common/constants.hpp"
#include "common/vec3.hpp"

#include <cmath>

namespace capsim {

struct ShearedLattice {
  double L = 1; // box side
  double s = 0; // strain offset in [-1/2, 1/2)
};

CAPSIM_HD double wrap_half(double v) {
  return v - std::floor(v + 0.5);
}

CAPSIM_HD ShearedLattice make_sheared_lattice(double L, double strain) {
  return {L, wrap_half(strain)};
}

// Lattice point n1 a1 + n2 a2 + n3 a3.
CAPSIM_HD Vec3 lattice_point(const ShearedLattice& g, double n1, double n2, double n3) {
  return {g.L * (n1 + g.s * n2), g.L * n2, g.L * n3};
}

// Reciprocal lattice point m1 b1 + m2 b2 + m3 b3.
CAPSIM_HD Vec3 reciprocal_point(const ShearedLattice& g, double m1, double m2,
                                double m3) {
  const double c = 2.0 * kPi / g.L;
  return {c * m1, c * (m2 - g.s * m1), c * m3};
}

// The image of r closest to the origin in fractional coordinates (each in [-1/2, 1/2)).
CAPSIM_HD Vec3 wrap_to_cell(const ShearedLattice& g, Vec3 r) {
  double f2 = wrap_half(r.y / g.L), f3 = wrap_half(r.z / g.L);
  double f1 = wrap_half((r.x - g.s * r.y) / g.L);
  return lattice_point(g, f1, f2, f3);
}

} // namespace capsim
