#include "stokes/spectral_ewald.hpp"

#include "stokes/ewald_kernel.hpp"
#include "stokes/stokeslet.hpp"

#include <cmath>
#include <complex>
#include <fftw3.h>
#include <omp.h>
#include <stdexcept>

namespace capsim {

SpectralParameters choose_spectral_parameters(double L, const EwaldParameters& ewald,
                                              double tolerance) {
  SpectralParameters p;
  p.support = std::max(4, int(std::ceil(-2.0 * std::log(tolerance) / kPi)) + 1);
  // |k| < k_cut needs |m1|, |m3| <= k_cut L / 2 pi and |m2| <= 1.5 k_cut L / 2 pi
  // (shear).
  const int m_max = int(std::ceil(1.5 * ewald.k_cut * L / (2.0 * kPi)));
  p.grid = std::max(2 * m_max + 2, p.support + 2);
  p.grid += p.grid % 2;
  const double h = L / p.grid, w = p.support * h / 2.0;
  const double m = 0.976 * std::sqrt(kPi * p.support);
  p.eta = std::pow(2.0 * w * ewald.xi / m, 2);
  if (!(p.eta > 0 && p.eta < 1))
    throw std::invalid_argument(
        "spectral Ewald: eta out of (0, 1); raise the tolerance or xi");
  return p;
}

struct SpectralEwald::Impl {
  double L, xi;
  SpectralParameters p;
  size_t n_real, n_complex;
  double* grid[3];
  fftw_complex* spectrum[3];
  fftw_plan forward, backward;

  double gauss_norm() const { return std::pow(2.0 * xi * xi / (kPi * p.eta), 1.5); }
  double gauss_rate() const { return 2.0 * xi * xi / p.eta; }
  size_t index(int j1, int j2, int j3) const {
    const int m = p.grid;
    auto w = [m](int j) { return ((j % m) + m) % m; };
    return (size_t(w(j1)) * m + w(j2)) * m + w(j3);
  }
  template <class Visit> void stencil(const ShearedLattice& g, Vec3 y, Visit visit) const;
  void scale_spectrum(const ShearedLattice& g);
};

// Visits the P^3 grid points around y with their Gaussian weight g(z_j - y). The j1 range
// is re-centred for every j2, so the stencil follows the sheared cell exactly.
template <class Visit>
void SpectralEwald::Impl::stencil(const ShearedLattice& g, Vec3 y, Visit visit) const {
  const int m = p.grid, half = p.support / 2;
  const double h = L / m, rate = gauss_rate();
  const double u2 = y.y / L * m, u3 = y.z / L * m, u1 = (y.x - g.s * y.y) / L * m;
  const int c2 = int(std::floor(u2)) - half + 1, c3 = int(std::floor(u3)) - half + 1;
  double gz[64];
  for (int b = 0; b < p.support; ++b) {
    double dz = (c3 + b - u3) * h;
    gz[b] = std::exp(-rate * dz * dz);
  }
  for (int a2 = 0; a2 < p.support; ++a2) {
    const int j2 = c2 + a2;
    const double dy = (j2 - u2) * h, gy = std::exp(-rate * dy * dy);
    const double centre1 = u1 - g.s * (j2 - u2); // x-offset zero at this j1
    const int c1 = int(std::floor(centre1)) - half + 1;
    for (int a1 = 0; a1 < p.support; ++a1) {
      const int j1 = c1 + a1;
      const double dx = ((j1 - u1) + g.s * (j2 - u2)) * h;
      const double gxy = gauss_norm() * gy * std::exp(-rate * dx * dx);
      for (int b = 0; b < p.support; ++b)
        visit(index(j1, j2, c3 + b), gxy * gz[b]);
    }
  }
}

// Multiplies the transformed grid by (8 pi / V)(V / M^3) J^EII-type kernel with the
// remaining Gaussian: (I/k^2 - k k/k^4)(1 + q + 2 q^2) exp(-(1 - eta) q), q = k^2/(4
// xi^2).
void SpectralEwald::Impl::scale_spectrum(const ShearedLattice& g) {
  const int m = p.grid, mh = m / 2 + 1;
  const double c = 8.0 * kPi / double(size_t(m) * m * m);
#pragma omp parallel for schedule(static)
  for (int i1 = 0; i1 < m; ++i1)
    for (int i2 = 0; i2 < m; ++i2)
      for (int i3 = 0; i3 < mh; ++i3) {
        const size_t k_index = (size_t(i1) * m + i2) * mh + i3;
        const int m1 = i1 <= m / 2 ? i1 : i1 - m, m2 = i2 <= m / 2 ? i2 : i2 - m;
        const bool nyquist =
            2 * std::abs(m1) == m || 2 * std::abs(m2) == m || 2 * i3 == m;
        Vec3 k = reciprocal_point(g, m1, m2, i3);
        double k2 = dot(k, k);
        if (nyquist || k2 == 0) {
          for (auto* s : spectrum)
            s[k_index][0] = s[k_index][1] = 0;
          continue;
        }
        double q = k2 / (4.0 * xi * xi);
        double w = c * (1.0 + q + 2.0 * q * q) * std::exp(-(1.0 - p.eta) * q) / k2;
        for (int part = 0; part < 2; ++part) {
          Vec3 f{spectrum[0][k_index][part], spectrum[1][k_index][part],
                 spectrum[2][k_index][part]};
          Vec3 r = w * (f - (dot(k, f) / k2) * k);
          spectrum[0][k_index][part] = r.x;
          spectrum[1][k_index][part] = r.y;
          spectrum[2][k_index][part] = r.z;
        }
      }
}

SpectralEwald::SpectralEwald(double L, const EwaldParameters& ewald,
                             const SpectralParameters& p)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.L = L;
  s.xi = ewald.xi;
  s.p = p;
  const int m = p.grid;
  s.n_real = size_t(m) * m * m;
  s.n_complex = size_t(m) * m * (m / 2 + 1);
  for (int a = 0; a < 3; ++a) {
    s.grid[a] = fftw_alloc_real(s.n_real);
    s.spectrum[a] = fftw_alloc_complex(s.n_complex);
  }
  // Planned once (FFTW_ESTIMATE leaves the arrays untouched); executed on all three
  // components through the new-array interface.
  s.forward = fftw_plan_dft_r2c_3d(m, m, m, s.grid[0], s.spectrum[0], FFTW_ESTIMATE);
  s.backward = fftw_plan_dft_c2r_3d(m, m, m, s.spectrum[0], s.grid[0], FFTW_ESTIMATE);
}

SpectralEwald::~SpectralEwald() {
  fftw_destroy_plan(impl_->forward);
  fftw_destroy_plan(impl_->backward);
  for (int a = 0; a < 3; ++a) {
    fftw_free(impl_->grid[a]);
    fftw_free(impl_->spectrum[a]);
  }
}

void SpectralEwald::add_reciprocal(const ShearedLattice& g, const FarSources& src,
                                   const std::vector<Vec3>& targets, std::vector<Vec3>& u,
                                   SpectralTimings* timings) {
  Impl& s = *impl_;
  const double t0 = omp_get_wtime();
  for (auto* grid : s.grid)
    std::fill(grid, grid + s.n_real, 0.0);
  for (size_t k = 0; k < src.size(); ++k) { // serial: stencils of sources overlap
    const Vec3 y{src.y[0][k], src.y[1][k], src.y[2][k]};
    const double f[3] = {src.f[0][k], src.f[1][k], src.f[2][k]};
    s.stencil(g, y, [&](size_t j, double w) {
      for (int a = 0; a < 3; ++a)
        s.grid[a][j] += w * f[a];
    });
  }
  const double t1 = omp_get_wtime();
  for (int a = 0; a < 3; ++a)
    fftw_execute_dft_r2c(s.forward, s.grid[a], s.spectrum[a]);
  s.scale_spectrum(g);
  for (int a = 0; a < 3; ++a)
    fftw_execute_dft_c2r(s.backward, s.spectrum[a], s.grid[a]);
  const double t2 = omp_get_wtime();
  const double cell = g.L * g.L * g.L / double(s.n_real); // V / M^3
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < targets.size(); ++i) {
    Vec3 sum;
    s.stencil(g, targets[i], [&](size_t j, double w) {
      sum += w * Vec3{s.grid[0][j], s.grid[1][j], s.grid[2][j]};
    });
    u[i] += cell * sum;
  }
  if (timings) {
    timings->spread += t1 - t0;
    timings->fft += t2 - t1;
    timings->gather += omp_get_wtime() - t2;
  }
}

} // namespace capsim
