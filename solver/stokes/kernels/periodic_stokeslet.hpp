#pragma once
// The periodic Stokeslet J^E of a sheared lattice (paper eq. 2.3) by plain Ewald sums:
// the reference kernel behind `capsim greens` and the tests of the fast methods.
#include "common/constants.hpp"
#include "common/vec3.hpp"
#include "stokes/cells/sheared_lattice.hpp"

#include <cmath>
#include <vector>

namespace capsim {

struct EwaldParameters {
  double xi = 0;            // splitting parameter
  double r_cut = 0;         // real-space images with |r_n| < r_cut
  double k_cut = 0;         // wave vectors with 0 < |k| < k_cut
  bool single_real = false; // the CPU's real-space sum in single precision
};

// Cut-offs for a relative truncation error ~ tolerance: the real-space terms decay like
// erfc(xi r) + (4/sqrt pi)(xi r)^3 exp(-xi^2 r^2), the reciprocal ones like
// (1 + q + 2 q^2) exp(-q) with q = k^2/(4 xi^2). xi <= 0 picks sqrt(pi)/L, which balances
// the number of real and reciprocal terms.
EwaldParameters choose_ewald_parameters(double L, double tolerance, double xi = 0);

// The xi that balances the cost of the direct sums for `targets` field points and
// `sources` quadrature points: real space ~ pair_cost * targets * sources * (4 pi/3)
// r_cut^3 / V, reciprocal space ~ (targets + sources) * (4 pi/3) (k_cut L / 2 pi)^3, with
// pair_cost the cost of one real-space pair in units of one (point, wave vector) term;
// equal when xi^6 = pair_cost targets sources pi^3 x_c^3 / ((targets + sources) V^2
// q_c^(3/2)), with x_c, q_c the dimensionless cut-offs of `tolerance`. Never below
// sqrt(pi)/L.
double balanced_xi(double L, double tolerance, long targets, long sources,
                   double pair_cost = 1.0);

// Calls visit(m1, m2, m3, k) for every wave vector k = m1 b1 + m2 b2 + m3 b3 of the
// sheared lattice with 0 < |k| < k_cut: m3 outermost, then m1, then m2 ascending, so the
// m2 of one (m1, m3) come together and consecutive (|k| < k_cut is a ball).
template <class Visit>
void for_each_wave_vector(const ShearedLattice& g, double k_cut, Visit visit) {
  const int m = int(std::ceil(k_cut * g.L / (2.0 * kPi))) + 1;
  for (int m3 = -m; m3 <= m; ++m3)
    for (int m1 = -m; m1 <= m; ++m1) {
      // k_y = 2 pi (m2 - s m1) / L: centre the m2 range on s m1.
      const int centre = int(std::round(g.s * m1));
      for (int m2 = centre - m - 1; m2 <= centre + m + 1; ++m2) {
        const Vec3 k = reciprocal_point(g, m1, m2, m3);
        const double kk = norm(k);
        if (kk > 0 && kk < k_cut)
          visit(m1, m2, m3, k);
      }
    }
}

// Wave vectors of the sheared lattice with 0 < |k| < k_cut.
std::vector<Vec3> wave_vectors(const ShearedLattice& g, double k_cut);

struct EwaldCounts {
  long images = 0, wave_vectors = 0;
};

// J^E(r) as a 3x3 tensor (normalisation of eq. 2.2: v = -1/(8 pi mu) J^E q).
Mat3 periodic_stokeslet(const ShearedLattice& lattice, Vec3 r, const EwaldParameters& p,
                        EwaldCounts* counts = nullptr);

} // namespace capsim
