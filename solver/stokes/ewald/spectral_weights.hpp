#pragma once
// Pointwise parts of Spectral Ewald (Lindbo & Tornberg 2011; see spectral_ewald.hpp) on
// the sheared lattice, host-device so that a GPU backend spreads, scales and gathers with
// the same weights as the CPU:
//  - the Gaussian g(r) = prod_d (2 xi^2/(pi eta_d))^(1/2) exp(-2 xi^2 r_d^2/eta_d)
//    evaluated at the P^3 grid points around a point (fractional coordinates, the j0
//    range re-centred for every j1 so that the stencil follows the sheared cell);
//  - the Fourier multiplier of the grid: the Stokes k-space kernel with the remaining
//    Gaussian exp(-sum_d (1 - eta_d) k_d^2/(4 xi^2)).
#include "common/constants.hpp"
#include "common/fast_special.hpp"
#include "common/vec3.hpp"
#include "stokes/cells/sheared_lattice.hpp"

#include <cmath>
#include <cstddef>

namespace capsim {

// Largest support P the stencils handle (P ~ -2 ln(tol)/pi + 1 is 19 at tol = 1e-12).
constexpr int kMaxSpreadSupport = 32;

// The grid and its Gaussian. Directions: 0 = x (flow), 1 = y (the sheared direction,
// which needs more wave numbers: k_y = 2 pi (m2 - s m1) / L), 2 = z; row-major index
// (j0 m[1] + j1) m[2] + j2. The Gaussian is separable in x, y, z with a rate per
// direction, g = scale exp(-sum_d rate_d r_d^2), rate_d = 2 xi^2 / eta_d: the same shape
// in units of each direction's spacing h_d, so P points of support truncate it alike.
struct SpreadGrid {
  double L = 1;                        // box side
  int m[3] = {};                       // grid points per direction
  int support = 0;                     // P grid points of Gaussian support per direction
  double h[3] = {};                    // spacing L / m_d
  double rate[3] = {};                 // 2 xi^2 / eta_d
  double eta[3] = {};                  // Gaussian splitting per direction, in (0, 1)
  double scale = 0;                    // prod_d sqrt(rate_d / pi): unit integral
  double ramp[kMaxSpreadSupport] = {}; // exp(-rate_0 a^2 h_0^2), a = 0 .. P-1
};

CAPSIM_HD SpreadGrid make_spread_grid(double L, const int m[3], int support, double xi,
                                      const double eta[3]) {
  SpreadGrid s;
  s.L = L, s.support = support, s.scale = 1;
  for (int d = 0; d < 3; ++d) {
    s.m[d] = m[d];
    s.h[d] = L / m[d];
    s.eta[d] = eta[d];
    s.rate[d] = 2.0 * xi * xi / eta[d];
    s.scale *= std::sqrt(s.rate[d] / kPi);
  }
  for (int a = 0; a < support && a < kMaxSpreadSupport; ++a)
    s.ramp[a] = std::exp(-s.rate[0] * a * a * s.h[0] * s.h[0]);
  return s;
}

// Grid points of the whole grid.
CAPSIM_HD std::size_t grid_points(const SpreadGrid& s) {
  return std::size_t(s.m[0]) * s.m[1] * s.m[2];
}

// Modes of the half spectrum of a real-to-complex transform of the grid.
CAPSIM_HD std::size_t spectrum_modes(const SpreadGrid& s) {
  return std::size_t(s.m[0]) * s.m[1] * (s.m[2] / 2 + 1);
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
  const int m = s.m[2];
  const double h = s.h[2], u3 = y.z / s.L * m;
  const int c3 = int(std::floor(u3)) - s.support / 2 + 1;
  SpreadColumn column;
  for (int b = 0; b < s.support; ++b) {
    const double dz = (c3 + b - u3) * h;
    column.index[b] = wrap_grid_index(c3 + b, m);
    column.weight[b] = exp_nonpositive(-s.rate[2] * dz * dz);
  }
  column.contiguous = column.index[0] + s.support <= m;
  return column;
}

// Visits the P^3 grid points around y as P^2 rows along the third grid direction:
// row(base, w) for the points base + column.index[b] (row-major index (j0 m1 + j1) m2 +
// j2) with Gaussian weights g(z_j - y) = w column.weight[b], column = spread_column(s,
// y). The j0 range is re-centred for every j1, so the stencil follows the sheared cell
// exactly: grid point (j0, j1) lies (j0 - u0) h0 + s (j1 - u1) h1 along x from y. Along
// j0 the weights come from the recurrence exp(-rate (d + a h)^2) = exp(-rate d^2)
// exp(-2 rate d h)^a exp(-rate a^2 h^2) (Greengard & Lee's fast Gaussian gridding): two
// exponentials per row instead of P.
template <class Row>
CAPSIM_HD_INLINE void for_each_spread_row(const SpreadGrid& s, const ShearedLattice& g,
                                          Vec3 y, Row row) {
  const int half = s.support / 2;
  const double h0 = s.h[0], h1 = s.h[1], rate0 = s.rate[0], rate1 = s.rate[1];
  const double u1 = y.y / h1, u0 = (y.x - g.s * y.y) / h0;
  const int c1 = int(std::floor(u1)) - half + 1;
  for (int a1 = 0; a1 < s.support; ++a1) {
    const int j1 = c1 + a1;
    const double dy = (j1 - u1) * h1, gy = s.scale * exp_nonpositive(-rate1 * dy * dy);
    const double shift = g.s * dy; // x of grid point (u0, j1) - x of y
    const int c0 = int(std::floor(u0 - shift / h0)) - half + 1;
    const double d0 = (c0 - u0) * h0 + shift;
    // d0 < 0 (the stencil starts left of y): 1/exp of a non-positive argument, the
    // branch-free exp instead of the library's (2 % of a step in it).
    const double step = 1.0 / exp_nonpositive(2.0 * rate0 * d0 * h0);
    double gx = gy * exp_nonpositive(-rate0 * d0 * d0);
    const std::size_t j1w = std::size_t(wrap_grid_index(j1, s.m[1]));
    for (int a0 = 0; a0 < s.support; ++a0, gx *= step)
      row((std::size_t(wrap_grid_index(c0 + a0, s.m[0])) * s.m[1] + j1w) * s.m[2],
          gx * s.ramp[a0]);
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

// The scalar part of the grid multiplier at wave vector k: (1 + q + 2 q^2) exp(-q) / k^2,
// q = k^2/(4 xi^2) (eq. 2.5's weight), with the two spread Gaussians' transform
// exp(-sum_d eta_d k_d^2 / (4 xi^2)) divided out: one exponential of a non-positive
// argument (every eta_d < 1).
CAPSIM_HD double spectral_multiplier_weight(Vec3 k, double xi, const double eta[3]) {
  const double k2 = dot(k, k), c = 1.0 / (4.0 * xi * xi), q = k2 * c;
  const double left = (1.0 - eta[0]) * k.x * k.x + (1.0 - eta[1]) * k.y * k.y +
                      (1.0 - eta[2]) * k.z * k.z;
  return (1.0 + q + 2.0 * q * q) * exp_nonpositive(-left * c) / k2;
}

// The grid multiplier applied to the transformed, spread force f at wave vector k:
// weight (I - k k/k^2) f.
CAPSIM_HD Vec3 spectral_multiplier_apply(Vec3 k, Vec3 f, double xi, const double eta[3]) {
  const double k2 = dot(k, k);
  return spectral_multiplier_weight(k, xi, eta) * (f - (dot(k, f) / k2) * k);
}

// The wave vector k = n0 b1 + n1 b2 + i2 b3 of mode (i0, i1, i2) of the r2c-transformed
// grid (i2 <= m2/2).
CAPSIM_HD Vec3 spectral_mode_vector(const ShearedLattice& g, const SpreadGrid& s, int i0,
                                    int i1, int i2) {
  return reciprocal_point(g, fft_wave_number(s.m[0], i0), fft_wave_number(s.m[1], i1),
                          i2);
}

// The multiplier of mode (i0, i1, i2) times c; zero at k = 0 (the mean flow, fixed by
// the frame) and at the Nyquist modes (no symmetric partner). Branch-free, so that a loop
// over i2 vectorises.
CAPSIM_HD_INLINE double spectral_mode_weight(const ShearedLattice& g, const SpreadGrid& s,
                                             int i0, int i1, int i2, double xi,
                                             double c) {
  const int n0 = fft_wave_number(s.m[0], i0), n1 = fft_wave_number(s.m[1], i1);
  const bool nyquist = 2 * n0 == s.m[0] || 2 * n0 == -s.m[0] || 2 * n1 == s.m[1] ||
                       2 * n1 == -s.m[1] || 2 * i2 == s.m[2];
  const Vec3 k = spectral_mode_vector(g, s, i0, i1, i2);
  const double k2 = dot(k, k);
  const double w = c * spectral_multiplier_weight(k, xi, s.eta); // inf at k = 0
  return nyquist || k2 == 0 ? 0.0 : w;
}

// Applies weight w (spectral_mode_weight) and the projection I - k k / k^2 to the real
// and the imaginary parts of the three components of mode k.
CAPSIM_HD void project_spectral_mode(Vec3 k, double w, double re[3], double im[3]) {
  const double k2 = dot(k, k);
  if (w == 0) { // k = 0 among them: no projection
    for (int a = 0; a < 3; ++a)
      re[a] = im[a] = 0;
    return;
  }
  const double kr = dot(k, {re[0], re[1], re[2]}) / k2;
  const double ki = dot(k, {im[0], im[1], im[2]}) / k2;
  const double kc[3] = {k.x, k.y, k.z};
  for (int a = 0; a < 3; ++a) {
    re[a] = w * (re[a] - kr * kc[a]);
    im[a] = w * (im[a] - ki * kc[a]);
  }
}

// Scales one mode (i0, i1, i2) of the r2c-transformed grid in place: the multiplier times
// c, projected (the two functions above).
CAPSIM_HD void scale_spectral_mode(const ShearedLattice& g, const SpreadGrid& s, int i0,
                                   int i1, int i2, double xi, double c, double re[3],
                                   double im[3]) {
  project_spectral_mode(spectral_mode_vector(g, s, i0, i1, i2),
                        spectral_mode_weight(g, s, i0, i1, i2, xi, c), re, im);
}

// The stresslet (af Klinteberg & Tornberg 2014; stokes/double_layer/ewald_stresslet.hpp):
// Hasimoto's screening phi(k) = (1 + q) exp(-q), q = k^2/(4 xi^2), with the two spread
// Gaussians' transform divided out, as spectral_multiplier_weight does for the stokeslet.
CAPSIM_HD double stresslet_multiplier_weight(Vec3 k, double xi, const double eta[3]) {
  const double k2 = dot(k, k), c = 1.0 / (4.0 * xi * xi), q = k2 * c;
  const double left = (1.0 - eta[0]) * k.x * k.x + (1.0 - eta[1]) * k.y * k.y +
                      (1.0 - eta[2]) * k.z * k.z;
  return (1.0 + q) * exp_nonpositive(-left * c);
}

// The stresslet multiplier of mode (i0, i1, i2) times c; zero at k = 0 (T^_ijk has no
// limit there and the periodic stresslet omits it: periodic_double_layer.hpp) and at the
// Nyquist modes, as spectral_mode_weight.
CAPSIM_HD_INLINE double stresslet_mode_weight(const ShearedLattice& g,
                                              const SpreadGrid& s, int i0, int i1, int i2,
                                              double xi, double c) {
  const int n0 = fft_wave_number(s.m[0], i0), n1 = fft_wave_number(s.m[1], i1);
  const bool nyquist = 2 * n0 == s.m[0] || 2 * n0 == -s.m[0] || 2 * n1 == s.m[1] ||
                       2 * n1 == -s.m[1] || 2 * i2 == s.m[2];
  const Vec3 k = spectral_mode_vector(g, s, i0, i1, i2);
  const double w = c * stresslet_multiplier_weight(k, xi, s.eta);
  return nyquist || dot(k, k) == 0 ? 0.0 : w;
}

// The stresslet's grid mode: the transformed source tensor S (the symmetric part of
// u a^T, whose six entries xx, yy, zz, xy, xz, yz are re[0..5], im[0..5]) mapped to
// w i A_ijl(k) S_jl, A of ewald_stresslet.hpp (3):
//   A(k) : S = (tr S k + 2 S k) / k^2 - 2 (k . S k) k / k^4,
// only S's symmetric part and trace entering, which is why six grids suffice (af
// Klinteberg & Tornberg 2014, section 3). The result goes to re[0..2], im[0..2].
CAPSIM_HD void stresslet_spectral_mode(Vec3 k, double w, double re[6], double im[6]) {
  if (w == 0) {
    for (int a = 0; a < 3; ++a)
      re[a] = im[a] = 0;
    return;
  }
  const double k2 = dot(k, k), inv_k2 = 1.0 / k2;
  auto contract = [&](const double* s) {
    const Vec3 sk{s[0] * k.x + s[3] * k.y + s[4] * k.z,
                  s[3] * k.x + s[1] * k.y + s[5] * k.z,
                  s[4] * k.x + s[5] * k.y + s[2] * k.z};
    const double tr = s[0] + s[1] + s[2], ksk = dot(k, sk);
    return inv_k2 * ((tr - 2.0 * ksk * inv_k2) * k + 2.0 * sk);
  };
  const Vec3 ar = contract(re), ai = contract(im);
  // i (ar + i ai) = -ai + i ar
  re[0] = -w * ai.x, re[1] = -w * ai.y, re[2] = -w * ai.z;
  im[0] = w * ar.x, im[1] = w * ar.y, im[2] = w * ar.z;
}

// The stresslet's self-matrix mode: the transformed normals a (re[0..2], im[0..2]) mapped
// to the symmetric matrix w i A_ijl(k) a_l (xx, yy, zz, xy, xz, yz in re[0..5],
// im[0..5]), A_ijl a_l = (d_ij (k . a) + k_i a_j + a_i k_j) / k^2 - 2 k_i k_j (k . a) /
// k^4 (symmetric_rank3_add_matrix of ewald_stresslet.hpp with v = k).
CAPSIM_HD void stresslet_matrix_spectral_mode(Vec3 k, double w, double re[6],
                                              double im[6]) {
  if (w == 0) {
    for (int a = 0; a < 6; ++a)
      re[a] = im[a] = 0;
    return;
  }
  const double inv_k2 = 1.0 / dot(k, k);
  auto contract = [&](const double* v, double* m) {
    const Vec3 a{v[0], v[1], v[2]};
    const double ka = dot(k, a), e = -2.0 * ka * inv_k2 * inv_k2;
    m[0] = inv_k2 * (2.0 * a.x * k.x + ka) + e * k.x * k.x;
    m[1] = inv_k2 * (2.0 * a.y * k.y + ka) + e * k.y * k.y;
    m[2] = inv_k2 * (2.0 * a.z * k.z + ka) + e * k.z * k.z;
    m[3] = inv_k2 * (a.x * k.y + k.x * a.y) + e * k.x * k.y;
    m[4] = inv_k2 * (a.x * k.z + k.x * a.z) + e * k.x * k.z;
    m[5] = inv_k2 * (a.y * k.z + k.y * a.z) + e * k.y * k.z;
  };
  double mr[6], mi[6];
  contract(re, mr);
  contract(im, mi);
  // i (mr + i mi) = -mi + i mr
  for (int a = 0; a < 6; ++a)
    re[a] = -w * mi[a], im[a] = w * mr[a];
}

} // namespace capsim
