#pragma once
// Pointwise parts of Spectral Ewald (Lindbo & Tornberg 2011; see spectral_ewald.hpp) on
// the sheared lattice, host-device so that a GPU backend spreads, scales and gathers with
// the same weights as the CPU:
//  - the Gaussian g(r) = (2 xi^2/(pi eta))^(3/2) exp(-2 xi^2 r^2/eta) evaluated at the
//    P^3 grid points around a point (fractional coordinates, the j1 range re-centred
//    for every j2 so that the stencil follows the sheared cell);
//  - the Fourier multiplier of the grid: the Stokes k-space kernel with the remaining
//    Gaussian exp(-(1 - eta) k^2/(4 xi^2)).
#include "common/fast_special.hpp"
#include "common/vec3.hpp"
#include "stokes/sheared_lattice.hpp"

#include <cmath>
#include <cstddef>

namespace capsim {

// Largest support P the stencils handle (P ~ -2 ln(tol)/pi + 1 is 19 at tol = 1e-12).
constexpr int kMaxSpreadSupport = 32;

struct SpreadGrid {
  double L = 1;                        // box side
  int m = 0;                           // grid points per direction
  int support = 0;                     // P grid points of Gaussian support per direction
  double rate = 0;                     // 2 xi^2 / eta: g = scale exp(-rate r^2)
  double scale = 0;                    // (2 xi^2 / (pi eta))^(3/2)
  double ramp[kMaxSpreadSupport] = {}; // exp(-rate a^2 h^2), a = 0 .. P-1
};

CAPSIM_HD SpreadGrid make_spread_grid(double L, int m, int support, double xi,
                                      double eta) {
  SpreadGrid s;
  s.L = L, s.m = m, s.support = support;
  s.rate = 2.0 * xi * xi / eta;
  s.scale = std::pow(s.rate / 3.14159265358979323846, 1.5);
  const double h = L / m;
  for (int a = 0; a < support && a < kMaxSpreadSupport; ++a)
    s.ramp[a] = std::exp(-s.rate * a * a * h * h);
  return s;
}

// Grid index j (any sign) wrapped into [0, m).
CAPSIM_HD int wrap_grid_index(int j, int m) {
  return ((j % m) + m) % m;
}

// The column of a stencil along the third grid direction: wrapped indices j3 and the
// Gaussian factors along it (the same for every row of the stencil of y).
struct SpreadColumn {
  int index[kMaxSpreadSupport];
  double weight[kMaxSpreadSupport];
  bool contiguous; // index[b] = index[0] + b: the column does not wrap around the grid
};

CAPSIM_HD_INLINE SpreadColumn spread_column(const SpreadGrid& s, Vec3 y) {
  const int m = s.m;
  const double h = s.L / m, u3 = y.z / s.L * m;
  const int c3 = int(std::floor(u3)) - s.support / 2 + 1;
  SpreadColumn column;
  for (int b = 0; b < s.support; ++b) {
    const double dz = (c3 + b - u3) * h;
    column.index[b] = wrap_grid_index(c3 + b, m);
    column.weight[b] = exp_nonpositive(-s.rate * dz * dz);
  }
  column.contiguous = column.index[0] + s.support <= m;
  return column;
}

// Visits the P^3 grid points around y as P^2 rows along the third grid direction:
// row(base, w) for the points base + column.index[b] (row-major index (j1 m + j2) m + j3)
// with Gaussian weights g(z_j - y) = w column.weight[b], column = spread_column(s, y).
// The j1 range is re-centred for every j2, so the stencil follows the sheared cell
// exactly. Along j1 the weights come from the recurrence exp(-rate (d + a h)^2) =
// exp(-rate d^2) exp(-2 rate d h)^a exp(-rate a^2 h^2) (Greengard & Lee's fast Gaussian
// gridding): two exponentials per row instead of P.
template <class Row>
CAPSIM_HD_INLINE void for_each_spread_row(const SpreadGrid& s, const ShearedLattice& g,
                                          Vec3 y, Row row) {
  const int m = s.m, half = s.support / 2;
  const double h = s.L / m, rate = s.rate;
  const double u2 = y.y / s.L * m, u1 = (y.x - g.s * y.y) / s.L * m;
  const int c2 = int(std::floor(u2)) - half + 1;
  for (int a2 = 0; a2 < s.support; ++a2) {
    const int j2 = c2 + a2;
    const double dy = (j2 - u2) * h, gy = s.scale * exp_nonpositive(-rate * dy * dy);
    const double centre1 = u1 - g.s * (j2 - u2); // x-offset zero at this j1
    const int c1 = int(std::floor(centre1)) - half + 1;
    const double d0 = ((c1 - u1) + g.s * (j2 - u2)) * h;
    const double step = std::exp(-2.0 * rate * d0 * h);
    double gx = gy * exp_nonpositive(-rate * d0 * d0);
    const std::size_t j2w = std::size_t(wrap_grid_index(j2, m));
    for (int a1 = 0; a1 < s.support; ++a1, gx *= step)
      row((std::size_t(wrap_grid_index(c1 + a1, m)) * m + j2w) * m, gx * s.ramp[a1]);
  }
}

// Calls visit(index, g(z_j - y)) for the P^3 grid points z_j around y.
template <class Visit>
CAPSIM_HD void for_each_spread_point(const SpreadGrid& s, const ShearedLattice& g, Vec3 y,
                                     Visit visit) {
  const SpreadColumn c = spread_column(s, y);
  for_each_spread_row(s, g, y, [&](std::size_t base, double w) {
    for (int b = 0; b < s.support; ++b)
      visit(base + c.index[b], w * c.weight[b]);
  });
}

// The signed wave number of FFT index i on an m-point grid (i <= m/2 positive).
CAPSIM_HD int fft_wave_number(int m, int i) {
  return i <= m / 2 ? i : i - m;
}

// The scalar part of the grid multiplier at |k|^2 = k2: (1 + q + 2 q^2) exp(-(1 - eta) q)
// / k2, q = k^2/(4 xi^2): eq. 2.5's weight with the Gaussian part exp(-eta q) that
// spreading and gathering supply divided out.
CAPSIM_HD double spectral_multiplier_weight(double k2, double xi, double eta) {
  const double q = k2 / (4.0 * xi * xi);
  return (1.0 + q + 2.0 * q * q) * exp_nonpositive(-(1.0 - eta) * q) / k2;
}

// The grid multiplier applied to the transformed, spread force f at wave vector k:
// weight (I - k k/k^2) f.
CAPSIM_HD Vec3 spectral_multiplier_apply(Vec3 k, Vec3 f, double xi, double eta) {
  const double k2 = dot(k, k);
  return spectral_multiplier_weight(k2, xi, eta) * (f - (dot(k, f) / k2) * k);
}

// Scales one mode (i1, i2, i3) of the r2c-transformed grid (i3 <= m/2) in place: the
// multiplier at k = m1 b1 + m2 b2 + i3 b3 times c, on the real and the imaginary parts of
// the three components (one weight for both). k = 0 (the mean flow, fixed by the frame)
// and the Nyquist modes (no symmetric partner) are set to zero.
CAPSIM_HD void scale_spectral_mode(const ShearedLattice& g, int m, int i1, int i2, int i3,
                                   double xi, double eta, double c, double re[3],
                                   double im[3]) {
  const int m1 = fft_wave_number(m, i1), m2 = fft_wave_number(m, i2);
  const bool nyquist =
      2 * m1 == m || 2 * m1 == -m || 2 * m2 == m || 2 * m2 == -m || 2 * i3 == m;
  const Vec3 k = reciprocal_point(g, m1, m2, i3);
  const double k2 = dot(k, k);
  if (nyquist || k2 == 0) {
    for (int a = 0; a < 3; ++a)
      re[a] = im[a] = 0;
    return;
  }
  const double w = c * spectral_multiplier_weight(k2, xi, eta);
  const double kr = dot(k, {re[0], re[1], re[2]}) / k2;
  const double ki = dot(k, {im[0], im[1], im[2]}) / k2;
  const double kc[3] = {k.x, k.y, k.z};
  for (int a = 0; a < 3; ++a) {
    re[a] = w * (re[a] - kr * kc[a]);
    im[a] = w * (im[a] - ki * kc[a]);
  }
}

} // namespace capsim
