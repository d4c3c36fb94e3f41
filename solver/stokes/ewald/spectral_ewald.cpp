#include "stokes/ewald/spectral_ewald.hpp"

#include "common/vector_clones.hpp"
#include "stokes/ewald/spectral_weights.hpp"
#include "stokes/kernels/ewald_kernel.hpp"
#include "stokes/kernels/stokeslet.hpp"

#include <cmath>
#include <complex>
#include <fftw3.h>
#include <omp.h>
#include <stdexcept>

namespace capsim {

namespace {

// The smallest even n' >= n with no prime factor above 5: FFTW is several times slower on
// sizes with larger factors (a 242^3 grid, 2 * 11^2, took over 20 times longer than
// 240^3).
int fft_friendly_size(int n) {
  for (;; ++n) {
    if (n % 2)
      continue;
    int r = n;
    for (int f : {2, 3, 5})
      while (r % f == 0)
        r /= f;
    if (r == 1)
      return n;
  }
}

// Adds the sources `members` to the interleaved grid (grid[3 j + a]). Per source the
// column weights times the force are formed once (3 P values); when the column does not
// wrap around the grid, every stencil row is one contiguous run of 3 P grid values, a
// loop the compiler vectorises (wrapping columns, a few per cent, take the indexed path).
// T: the grid's precision (float where the tolerance allows: SpectralParameters).
template <class T>
CAPSIM_HD_INLINE void spread_sources_into(const SpreadGrid& sg, const ShearedLattice& g,
                                          const FarSources& src,
                                          const std::vector<int>& members, T* grid) {
  const int P = sg.support;
  T wf[3 * kMaxSpreadSupport];
  for (int k : members) {
    const Vec3 y{src.y[0][k], src.y[1][k], src.y[2][k]};
    const SpreadColumn c = spread_column(sg, y);
    for (int b = 0; b < P; ++b)
      for (int a = 0; a < 3; ++a)
        wf[3 * b + a] = T(c.weight[b] * src.f[a][k]);
    if (c.contiguous)
      for_each_spread_row(sg, g, y, [&](size_t base, double w) {
        T* row = grid + 3 * (base + c.index[0]);
        const T wt = T(w);
        for (int j = 0; j < 3 * P; ++j)
          row[j] += wt * wf[j];
      });
    else
      for_each_spread_row(sg, g, y, [&](size_t base, double w) {
        for (int b = 0; b < P; ++b)
          for (int a = 0; a < 3; ++a)
            grid[3 * (base + c.index[b]) + a] += T(w) * wf[3 * b + a];
      });
  }
}

CAPSIM_VECTOR_CLONES void spread_sources(const SpreadGrid& sg, const ShearedLattice& g,
                                         const FarSources& src,
                                         const std::vector<int>& members, double* grid) {
  spread_sources_into(sg, g, src, members, grid);
}

CAPSIM_VECTOR_CLONES void spread_sources(const SpreadGrid& sg, const ShearedLattice& g,
                                         const FarSources& src,
                                         const std::vector<int>& members, float* grid) {
  spread_sources_into(sg, g, src, members, grid);
}

// The gathered grid velocity at x: sum over the stencil of g(z_j - x) grid[j], with the
// rows summed as contiguous runs (as in spread_sources) and the column weights applied
// once at the end.
template <class T>
CAPSIM_HD_INLINE Vec3 gather_point_from(const SpreadGrid& sg, const ShearedLattice& g,
                                        const T* grid, Vec3 x) {
  const int P = sg.support;
  const SpreadColumn c = spread_column(sg, x);
  T acc[3 * kMaxSpreadSupport] = {};
  if (c.contiguous)
    for_each_spread_row(sg, g, x, [&](size_t base, double w) {
      const T* row = grid + 3 * (base + c.index[0]);
      const T wt = T(w);
      for (int j = 0; j < 3 * P; ++j)
        acc[j] += wt * row[j];
    });
  else
    for_each_spread_row(sg, g, x, [&](size_t base, double w) {
      for (int b = 0; b < P; ++b)
        for (int a = 0; a < 3; ++a)
          acc[3 * b + a] += T(w) * grid[3 * (base + c.index[b]) + a];
    });
  Vec3 sum;
  for (int b = 0; b < P; ++b)
    sum += c.weight[b] *
           Vec3{double(acc[3 * b]), double(acc[3 * b + 1]), double(acc[3 * b + 2])};
  return sum;
}

CAPSIM_VECTOR_CLONES Vec3 gather_point(const SpreadGrid& sg, const ShearedLattice& g,
                                       const double* grid, Vec3 x) {
  return gather_point_from(sg, g, grid, x);
}

CAPSIM_VECTOR_CLONES Vec3 gather_point(const SpreadGrid& sg, const ShearedLattice& g,
                                       const float* grid, Vec3 x) {
  return gather_point_from(sg, g, grid, x);
}

// The weights (spectral_mode_weight) of the modes i2 = 0 .. m2/2 of row (i0, i1).
CAPSIM_VECTOR_CLONES void row_weights(const ShearedLattice& g, const SpreadGrid& s,
                                      int i0, int i1, double xi, double c, double* w) {
  const int mh = s.m[2] / 2 + 1;
#pragma omp simd
  for (int i2 = 0; i2 < mh; ++i2)
    w[i2] = spectral_mode_weight(g, s, i0, i1, i2, xi, c);
}

} // namespace

SpectralParameters choose_spectral_parameters(double L, const EwaldParameters& ewald,
                                              double tolerance) {
  SpectralParameters p;
  p.support = std::max(4, int(std::ceil(-2.0 * std::log(tolerance) / kPi)) + 1);
  p.support += p.support % 2; // even: the stencil is centred on the point (odd P is not)
  // Wave numbers the grid carries, in units of k_cut L / 2 pi: y needs 1.5 for the shear;
  // x and z need only 1, but the deconvolution exp(eta_d k_d^2 / (4 xi^2)) amplifies the
  // aliased content of modes near the Nyquist: with no margin along x and z the error
  // reaches 2.9 times the tolerance at 1e-6, with 25 % it stays below it
  // (docs/performance.md, "Accuracy against the requested tolerance").
  constexpr double kReach[3] = {1.25, 1.5, 1.25};
  const double n_cut = ewald.k_cut * L / (2.0 * kPi),
               m = 0.976 * std::sqrt(kPi * p.support);
  for (int d = 0; d < 3; ++d) {
    const int n_max = int(std::ceil(kReach[d] * n_cut));
    p.grid[d] = fft_friendly_size(std::max(2 * n_max + 2, p.support + 2));
    const double w = p.support * (L / p.grid[d]) / 2.0;
    p.eta[d] = std::pow(2.0 * w * ewald.xi / m, 2);
    if (!(p.eta[d] > 0 && p.eta[d] < 1))
      throw std::invalid_argument(
          "spectral Ewald: eta out of (0, 1); raise the tolerance or xi");
  }
  return p;
}

double spectral_xi(double L, double tolerance, long nodes, long points) {
  // Seconds per real-space pair (gather and kernel) and per FFT point and log2 factor
  // (six transforms: three components each way), measured on one core of the project
  // machine (AVX-512); only their ratio matters.
  constexpr double kPairSeconds = 30e-9, kFftSeconds = 0.8e-9;
  const double density = double(points) / (L * L * L);
  double best_xi = 0, best_cost = 0;
  // r_cut from L/2 down to 0.2 capsule radii in steps of 5 %.
  for (double r_cut = L / 2.0; r_cut >= 0.2; r_cut *= 0.95) {
    const double x_cut = choose_ewald_parameters(L, tolerance, 1.0).r_cut;
    const EwaldParameters e = choose_ewald_parameters(L, tolerance, x_cut / r_cut);
    const SpectralParameters p = choose_spectral_parameters(L, e, tolerance);
    const double points = double(p.grid[0]) * p.grid[1] * p.grid[2];
    const double pairs = double(nodes) * density * 4.0 / 3.0 * kPi * std::pow(r_cut, 3);
    const double cost =
        kPairSeconds * pairs + kFftSeconds * 6.0 * points * std::log2(points);
    if (best_xi == 0 || cost < best_cost)
      best_xi = e.xi, best_cost = cost;
  }
  return best_xi;
}

struct SpectralEwald::Impl {
  double L, xi;
  SpectralParameters p;
  size_t n_real, n_complex;
  // The three force components interleaved (grid[3 j + a]): a stencil row is one run of
  // memory for all of them. Transformed together by one strided FFTW plan each way, in
  // double precision, or in single (p.single: FFTW's fftwf_ interface) where the
  // tolerance leaves room for its rounding.
  double* grid = nullptr;
  fftw_complex* spectrum = nullptr;
  fftw_plan forward = nullptr, backward = nullptr;
  float* grid_f = nullptr;
  fftwf_complex* spectrum_f = nullptr;
  fftwf_plan forward_f = nullptr, backward_f = nullptr;

  SpreadGrid spread_grid; // the Gaussian and its stencils (spectral_weights.hpp)
  template <class Complex>
  void scale_spectrum(const ShearedLattice& g, Complex* spectrum);
  template <class T>
  void spread(const ShearedLattice& g, const FarSources& src, T* grid) const;
  template <class T, class Complex, class Forward, class Backward>
  void evaluate(const ShearedLattice& g, const FarSources& src,
                const std::vector<Vec3>& targets, std::vector<Vec3>& u, T* grid,
                Complex* spectrum, Forward forward, Backward backward,
                SpectralTimings* timings);
};

// Spreads the sources to the grid in parallel without races: the sources are binned into
// slabs along the third grid direction, each at least P grid planes thick, so that a
// source's stencil touches only its own slab and the next; even slabs are spread
// concurrently, then odd ones. Each grid value receives its terms in the same order
// whatever the number of threads.
template <class T>
void SpectralEwald::Impl::spread(const ShearedLattice& g, const FarSources& src,
                                 T* grid) const {
  const int m = p.grid[2], half = p.support / 2;
  int slabs = m / p.support;
  slabs -= slabs % 2; // an even count: the last slab's neighbour, slab 0, is even
  if (slabs < 2)
    slabs = 1;
  std::vector<std::vector<int>> members(slabs);
  for (size_t k = 0; k < src.size(); ++k) {
    const int c3 = int(std::floor(src.y[2][k] / L * m)) - half + 1;
    members[std::min(slabs - 1, wrap_grid_index(c3, m) * slabs / m)].push_back(int(k));
  }
  auto spread_slab = [&](int slab) {
    spread_sources(spread_grid, g, src, members[slab], grid);
  };
  if (slabs == 1) {
    spread_slab(0);
    return;
  }
  for (int parity = 0; parity < 2; ++parity) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int slab = parity; slab < slabs; slab += 2)
      spread_slab(slab);
  }
}

// Multiplies the transformed grid by (8 pi / V)(V / (M_x M_y M_z)) J^EII-type kernel with
// the remaining Gaussian (spectral_weights.hpp): per row the weights in one vectorised
// loop (their exponentials were a twentieth of an evaluation at level 4 one mode at a
// time), then the projections.
template <class Complex>
void SpectralEwald::Impl::scale_spectrum(const ShearedLattice& g, Complex* spectrum) {
  const SpreadGrid& s = spread_grid;
  const int m1 = s.m[1], mh = s.m[2] / 2 + 1;
  const double c = 8.0 * kPi / double(grid_points(s));
#pragma omp parallel
  {
    std::vector<double> w(mh);
#pragma omp for schedule(static)
    for (int i0 = 0; i0 < s.m[0]; ++i0)
      for (int i1 = 0; i1 < m1; ++i1) {
        row_weights(g, s, i0, i1, xi, c, w.data());
        for (int i2 = 0; i2 < mh; ++i2) {
          const size_t k_index = (size_t(i0) * m1 + i1) * mh + i2;
          Complex* sk = spectrum + 3 * k_index;
          double re[3] = {sk[0][0], sk[1][0], sk[2][0]};
          double im[3] = {sk[0][1], sk[1][1], sk[2][1]};
          project_spectral_mode(spectral_mode_vector(g, s, i0, i1, i2), w[i2], re, im);
          for (int a = 0; a < 3; ++a)
            sk[a][0] = re[a], sk[a][1] = im[a];
        }
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
  if (p.support > kMaxSpreadSupport)
    throw std::invalid_argument("spectral Ewald: support above the stencil limit");
  s.spread_grid = make_spread_grid(L, p.grid, p.support, s.xi, p.eta);
  s.n_real = grid_points(s.spread_grid);
  s.n_complex = spectrum_modes(s.spread_grid);
  // Planned once (FFTW_ESTIMATE leaves the arrays untouched) for the threads of the run.
  const int* dims = p.grid;
  if (p.single) {
    static const bool threads_ready = fftwf_init_threads() != 0;
    if (threads_ready)
      fftwf_plan_with_nthreads(omp_get_max_threads());
    s.grid_f = fftwf_alloc_real(3 * s.n_real);
    s.spectrum_f = fftwf_alloc_complex(3 * s.n_complex);
    s.forward_f = fftwf_plan_many_dft_r2c(3, dims, 3, s.grid_f, nullptr, 3, 1,
                                          s.spectrum_f, nullptr, 3, 1, FFTW_ESTIMATE);
    s.backward_f = fftwf_plan_many_dft_c2r(3, dims, 3, s.spectrum_f, nullptr, 3, 1,
                                           s.grid_f, nullptr, 3, 1, FFTW_ESTIMATE);
    return;
  }
  static const bool threads_ready = fftw_init_threads() != 0;
  if (threads_ready)
    fftw_plan_with_nthreads(omp_get_max_threads());
  s.grid = fftw_alloc_real(3 * s.n_real);
  s.spectrum = fftw_alloc_complex(3 * s.n_complex);
  s.forward = fftw_plan_many_dft_r2c(3, dims, 3, s.grid, nullptr, 3, 1, s.spectrum,
                                     nullptr, 3, 1, FFTW_ESTIMATE);
  s.backward = fftw_plan_many_dft_c2r(3, dims, 3, s.spectrum, nullptr, 3, 1, s.grid,
                                      nullptr, 3, 1, FFTW_ESTIMATE);
}

SpectralEwald::~SpectralEwald() {
  Impl& s = *impl_;
  if (s.p.single) {
    fftwf_destroy_plan(s.forward_f);
    fftwf_destroy_plan(s.backward_f);
    fftwf_free(s.grid_f);
    fftwf_free(s.spectrum_f);
    return;
  }
  fftw_destroy_plan(s.forward);
  fftw_destroy_plan(s.backward);
  fftw_free(s.grid);
  fftw_free(s.spectrum);
}

// Spread, transform, scale, transform back and gather on the grid of precision T;
// forward() and backward() execute the matching FFTW plans.
template <class T, class Complex, class Forward, class Backward>
void SpectralEwald::Impl::evaluate(const ShearedLattice& g, const FarSources& src,
                                   const std::vector<Vec3>& targets, std::vector<Vec3>& u,
                                   T* grid, Complex* spectrum, Forward forward,
                                   Backward backward, SpectralTimings* timings) {
  const double t0 = omp_get_wtime();
  const long n_grid = long(3 * n_real);
#pragma omp parallel for schedule(static)
  for (long j = 0; j < n_grid; ++j)
    grid[j] = T(0);
  spread(g, src, grid);
  const double t1 = omp_get_wtime();
  forward();
  scale_spectrum(g, spectrum);
  backward();
  const double t2 = omp_get_wtime();
  const double cell = g.L * g.L * g.L / double(n_real); // V / (M_x M_y M_z)
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < targets.size(); ++i)
    u[i] += cell * gather_point(spread_grid, g, grid, targets[i]);
  if (timings) {
    timings->spread += t1 - t0;
    timings->fft += t2 - t1;
    timings->gather += omp_get_wtime() - t2;
  }
}

void SpectralEwald::add_reciprocal(const ShearedLattice& g, const FarSources& src,
                                   const std::vector<Vec3>& targets, std::vector<Vec3>& u,
                                   SpectralTimings* timings) {
  Impl& s = *impl_;
  if (s.p.single)
    s.evaluate(
        g, src, targets, u, s.grid_f, s.spectrum_f, [&] { fftwf_execute(s.forward_f); },
        [&] { fftwf_execute(s.backward_f); }, timings);
  else
    s.evaluate(
        g, src, targets, u, s.grid, s.spectrum, [&] { fftw_execute(s.forward); },
        [&] { fftw_execute(s.backward); }, timings);
}

} // namespace capsim
