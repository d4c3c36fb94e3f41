// The host-device pieces of Spectral Ewald (stokes/ewald/spectral_weights.hpp) that the CUDA
// backend runs: the Gaussian stencil, the grid multiplier, and the whole spread -> FFT ->
// scale -> gather chain built from them (here with FFTW) against direct k-space sums.
#include "stokes/kernels/ewald_kernel.hpp"
#include "stokes/ewald/ewald_reciprocal.hpp"
#include "stokes/ewald/spectral_ewald.hpp"
#include "stokes/ewald/spectral_weights.hpp"

#include <catch2/catch.hpp>
#include <complex>
#include <fftw3.h>
#include <random>

using namespace capsim;

namespace {

// The reciprocal-space velocity by the host-device pieces alone, the way a GPU runs them.
std::vector<Vec3> reciprocal_from_weights(const ShearedLattice& g, const SpreadGrid& s,
                                          double xi, const FarSources& src,
                                          const std::vector<Vec3>& targets) {
  const int* m = s.m;
  const int mh = m[2] / 2 + 1;
  const size_t n_real = grid_points(s), n_complex = spectrum_modes(s);
  std::vector<double> grid(3 * n_real, 0.0);
  std::vector<std::complex<double>> spec(3 * n_complex);
  for (size_t k = 0; k < src.size(); ++k)
    for_each_spread_point(s, g, {src.y[0][k], src.y[1][k], src.y[2][k]},
                          [&](size_t j, double w) {
                            for (int a = 0; a < 3; ++a)
                              grid[a * n_real + j] += w * src.f[a][k];
                          });
  for (int a = 0; a < 3; ++a) {
    auto* out = reinterpret_cast<fftw_complex*>(&spec[a * n_complex]);
    fftw_plan p =
        fftw_plan_dft_r2c_3d(m[0], m[1], m[2], &grid[a * n_real], out, FFTW_ESTIMATE);
    fftw_execute(p);
    fftw_destroy_plan(p);
  }
  const double c = 8.0 * kPi / double(n_real);
  for (int i0 = 0; i0 < m[0]; ++i0)
    for (int i1 = 0; i1 < m[1]; ++i1)
      for (int i2 = 0; i2 < mh; ++i2) {
        const size_t k = (size_t(i0) * m[1] + i1) * mh + i2;
        double re[3], im[3];
        for (int a = 0; a < 3; ++a)
          re[a] = spec[a * n_complex + k].real(), im[a] = spec[a * n_complex + k].imag();
        scale_spectral_mode(g, s, i0, i1, i2, xi, c, re, im);
        for (int a = 0; a < 3; ++a)
          spec[a * n_complex + k] = {re[a], im[a]};
      }
  for (int a = 0; a < 3; ++a) {
    auto* in = reinterpret_cast<fftw_complex*>(&spec[a * n_complex]);
    fftw_plan p =
        fftw_plan_dft_c2r_3d(m[0], m[1], m[2], in, &grid[a * n_real], FFTW_ESTIMATE);
    fftw_execute(p);
    fftw_destroy_plan(p);
  }
  const double cell = g.L * g.L * g.L / double(n_real);
  std::vector<Vec3> u(targets.size());
  for (size_t i = 0; i < targets.size(); ++i)
    for_each_spread_point(s, g, targets[i], [&](size_t j, double w) {
      u[i] += (cell * w) * Vec3{grid[j], grid[n_real + j], grid[2 * n_real + j]};
    });
  return u;
}

} // namespace

TEST_CASE("spectral weights: the stencil integrates the unit Gaussian and keeps its "
          "centre on a sheared grid",
          "[spectral][hd]") {
  // eta_d as choose_spectral_parameters sets it: truncation ~ exp(-0.476 pi P), 4e-11
  // here; the grid is finer along y, as for the sheared lattice.
  const double L = 4.0, xi = 1.5;
  const int m[3] = {32, 48, 32}, support = 16;
  const double shape = 0.976 * std::sqrt(kPi * support);
  double eta[3];
  for (int d = 0; d < 3; ++d)
    eta[d] = std::pow(support * (L / m[d]) * xi / shape, 2);
  const SpreadGrid s = make_spread_grid(L, m, support, xi, eta);
  const double cell = L * L * L / double(grid_points(s));
  for (double strain : {0.0, 0.4, -0.45}) {
    const ShearedLattice g = make_sheared_lattice(L, strain);
    for (Vec3 y : {Vec3{0.1, 0.2, 0.3}, Vec3{3.9, -1.7, 2.05}}) {
      double mass = 0;
      Vec3 centre;
      // Grid point position from its index, unwrapped to the image nearest y.
      for_each_spread_point(s, g, y, [&](size_t j, double w) {
        const int j2 = int(j % m[2]), j1 = int(j / m[2] % m[1]),
                  j0 = int(j / m[2] / m[1]);
        const Vec3 z =
            lattice_point(g, double(j0) / m[0], double(j1) / m[1], double(j2) / m[2]);
        mass += cell * w;
        centre += (cell * w) * (y + wrap_to_cell(g, z - y));
      });
      INFO("strain " << strain << " y " << y.x << " " << y.y << " " << y.z);
      CHECK(mass == Approx(1.0).epsilon(1e-9));
      CHECK(norm(centre - y) < 1e-9);
    }
  }
}

TEST_CASE("spectral weights: the grid multiplier is the Ewald k-space weight without the "
          "spread Gaussians",
          "[spectral][hd]") {
  const double xi = 1.3, eta[3] = {0.4, 0.2, 0.35};
  const Vec3 f{0.3, -1.1, 0.7};
  for (Vec3 k : {Vec3{1, 0, 0}, Vec3{0.5, -2.0, 1.5}, Vec3{-3, 4, 0.1}}) {
    const double spread = (eta[0] * k.x * k.x + eta[1] * k.y * k.y + eta[2] * k.z * k.z) /
                          (4 * xi * xi); // both Gaussians: exp(-spread) in all
    const Vec3 want = std::exp(spread) * ewald_recip_apply(k, f, xi);
    CHECK(norm(spectral_multiplier_apply(k, f, xi, eta) - want) < 1e-13 * norm(want));
  }
}

TEST_CASE("spectral weights: spread, FFT, scale and gather by the host-device pieces "
          "match direct k-space sums",
          "[spectral][hd]") {
  const double L = 5.0, xi = 1.2, tol = 1e-8;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pos(0, L), force(-1, 1);
  FarSources src;
  std::vector<Vec3> targets;
  Vec3 total;
  for (int k = 0; k < 200; ++k) {
    Vec3 f{force(rng), force(rng), force(rng)};
    if (k == 199)
      f = -1.0 * total;
    total += f;
    Vec3 y{pos(rng), pos(rng), pos(rng)};
    for (int a = 0; a < 3; ++a) {
      src.y[a].push_back((&y.x)[a]);
      src.f[a].push_back((&f.x)[a]);
    }
  }
  for (int i = 0; i < 40; ++i)
    targets.push_back({pos(rng), pos(rng), pos(rng)});
  const EwaldParameters e = choose_ewald_parameters(L, tol, xi);
  const SpectralParameters p = choose_spectral_parameters(L, e, tol);
  for (double strain : {0.0, 0.35}) {
    const ShearedLattice g = make_sheared_lattice(L, strain);
    std::vector<Vec3> ref(targets.size());
    ewald_reciprocal_direct(g, targets, src, choose_ewald_parameters(L, 1e-14, xi), ref);
    const std::vector<Vec3> u = reciprocal_from_weights(
        g, make_spread_grid(L, p.grid, p.support, xi, p.eta), xi, src, targets);
    double err = 0, size = 0;
    for (size_t i = 0; i < u.size(); ++i) {
      err += dot(u[i] - ref[i], u[i] - ref[i]);
      size += dot(ref[i], ref[i]);
    }
    INFO("strain " << strain << " grid " << p.grid[0] << " x " << p.grid[1] << " x "
                   << p.grid[2] << " support " << p.support);
    CHECK(std::sqrt(err / size) < 5 * tol);
  }
}
