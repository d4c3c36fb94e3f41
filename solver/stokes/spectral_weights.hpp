#pragma once
// Pointwise parts of Spectral Ewald (Lindbo & Tornberg 2011; see spectral_ewald.hpp) on
// the sheared lattice, host-device so that a GPU backend spreads, scales and gathers with
// the same weights as the CPU:
//  - the Gaussian g(r) = (2 xi^2/(pi eta))^(3/2) exp(-2 xi^2 r^2/eta) evaluated at the
//    P^3 grid points around a point (fractional coordinates, the j1 range re-centred
//    for every j2 so that the stencil follows the sheared cell);
//  - the Fourier multiplier of the grid: the Stokes k-space kernel with the remaining
//    Gaussian exp(-(1 - eta) k^2/(4 xi^2)).
#include "common/vec3.hpp"
#include "stokes/sheared_lattice.hpp"

#include <cmath>
#include <cstddef>

namespace capsim {

// Largest support P the stencils handle (P ~ -2 ln(tol)/pi + 1 is 19 at tol = 1e-12).
constexpr int kMaxSpreadSupport = 32;

struct SpreadGrid {
  double L = 1;     // box side
  int m = 0;        // grid points per direction
  int support = 0;  // P grid points of Gaussian support per direction
  double rate = 0;  // 2 xi^2 / eta: g = norm exp(-rate r^2)
  double scale = 0; // (2 xi^2 / (pi eta))^(3/2)
};

CAPSIM_HD SpreadGrid make_spread_grid(double L, int m, int support, double xi,
                                      double eta) {
  const double rate = 2.0 * xi * xi / eta;
  return {L, m, support, rate, std::pow(rate / 3.14159265358979323846, 1.5)};
}

// Row-major index of grid point (j1, j2, j3), each wrapped periodically into [0, m).
CAPSIM_HD std::size_t spread_grid_index(int m, int j1, int j2, int j3) {
  j1 = ((j1 % m) + m) % m;
  j2 = ((j2 % m) + m) % m;
  j3 = ((j3 % m) + m) % m;
  return (std::size_t(j1) * m + j2) * m + j3;
}

// Calls visit(index, g(z_j - y)) for the P^3 grid points z_j around y.
template <class Visit>
CAPSIM_HD void for_each_spread_point(const SpreadGrid& s, const ShearedLattice& g, Vec3 y,
                                     Visit visit) {
  const int m = s.m, half = s.support / 2;
  const double h = s.L / m;
  const double u2 = y.y / s.L * m, u3 = y.z / s.L * m, u1 = (y.x - g.s * y.y) / s.L * m;
  const int c2 = int(std::floor(u2)) - half + 1, c3 = int(std::floor(u3)) - half + 1;
  double gz[kMaxSpreadSupport];
  for (int b = 0; b < s.support; ++b) {
    const double dz = (c3 + b - u3) * h;
    gz[b] = std::exp(-s.rate * dz * dz);
  }
  for (int a2 = 0; a2 < s.support; ++a2) {
    const int j2 = c2 + a2;
    const double dy = (j2 - u2) * h, gy = std::exp(-s.rate * dy * dy);
    const double centre1 = u1 - g.s * (j2 - u2); // x-offset zero at this j1
    const int c1 = int(std::floor(centre1)) - half + 1;
    for (int a1 = 0; a1 < s.support; ++a1) {
      const int j1 = c1 + a1;
      const double dx = ((j1 - u1) + g.s * (j2 - u2)) * h;
      const double gxy = s.scale * gy * std::exp(-s.rate * dx * dx);
      for (int b = 0; b < s.support; ++b)
        visit(spread_grid_index(m, j1, j2, c3 + b), gxy * gz[b]);
    }
  }
}

// The signed wave number of FFT index i on an m-point grid (i <= m/2 positive).
CAPSIM_HD int fft_wave_number(int m, int i) {
  return i <= m / 2 ? i : i - m;
}

// The grid multiplier applied to the transformed, spread force f at wave vector k:
// (I/k^2 - k k/k^4)(1 + q + 2 q^2) exp(-(1 - eta) q) f, q = k^2/(4 xi^2): eq. 2.5's
// weight with the Gaussian part exp(-eta q) that spreading and gathering supply divided
// out.
CAPSIM_HD Vec3 spectral_multiplier_apply(Vec3 k, Vec3 f, double xi, double eta) {
  const double k2 = dot(k, k), q = k2 / (4.0 * xi * xi);
  const double w = (1.0 + q + 2.0 * q * q) * std::exp(-(1.0 - eta) * q) / k2;
  return w * (f - (dot(k, f) / k2) * k);
}

// Scales one mode (i1, i2, i3) of the r2c-transformed grid (i3 <= m/2) in place: the
// multiplier at k = m1 b1 + m2 b2 + i3 b3 times c, on the real and the imaginary parts of
// the three components. k = 0 (the mean flow, fixed by the frame) and the Nyquist modes
// (no symmetric partner) are set to zero.
CAPSIM_HD void scale_spectral_mode(const ShearedLattice& g, int m, int i1, int i2, int i3,
                                   double xi, double eta, double c, double re[3],
                                   double im[3]) {
  const int m1 = fft_wave_number(m, i1), m2 = fft_wave_number(m, i2);
  const bool nyquist =
      2 * m1 == m || 2 * m1 == -m || 2 * m2 == m || 2 * m2 == -m || 2 * i3 == m;
  const Vec3 k = reciprocal_point(g, m1, m2, i3);
  if (nyquist || dot(k, k) == 0) {
    for (int a = 0; a < 3; ++a)
      re[a] = im[a] = 0;
    return;
  }
  const Vec3 r = c * spectral_multiplier_apply(k, {re[0], re[1], re[2]}, xi, eta);
  const Vec3 i = c * spectral_multiplier_apply(k, {im[0], im[1], im[2]}, xi, eta);
  re[0] = r.x, re[1] = r.y, re[2] = r.z;
  im[0] = i.x, im[1] = i.y, im[2] = i.z;
}

} // namespace capsim
