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

// The source components of a grid: positions y and N values per point (the three forces
// of the stokeslet, the six entries of the stresslet's symmetric source tensor).
template <int N> struct GridSources {
  const std::vector<double>* y;    // y[3]
  const std::vector<double>* f[N]; // f[a][point]
  size_t size() const { return y[0].size(); }
};

// Adds the sources `members` to the interleaved grid (grid[N j + a]). Per source the
// column weights times the N components are formed once (N P values); when the column
// does not wrap around the grid, every stencil row is one contiguous run of N P grid
// values, a loop the compiler vectorises (wrapping columns, a few per cent, take the
// indexed path). T: the grid's precision (float where the tolerance allows:
// SpectralParameters).
template <int N, class T>
CAPSIM_HD_INLINE void spread_sources_into(const SpreadGrid& sg, const ShearedLattice& g,
                                          const GridSources<N>& src,
                                          const std::vector<int>& members, T* grid) {
  const int P = sg.support;
  T wf[N * kMaxSpreadSupport];
  for (int k : members) {
    const Vec3 y{src.y[0][k], src.y[1][k], src.y[2][k]};
    const SpreadColumn c = spread_column(sg, y);
    for (int b = 0; b < P; ++b)
      for (int a = 0; a < N; ++a)
        wf[N * b + a] = T(c.weight[b] * (*src.f[a])[k]);
    if (c.contiguous)
      for_each_spread_row(sg, g, y, [&](size_t base, double w) {
        T* row = grid + N * (base + c.index[0]);
        const T wt = T(w);
        for (int j = 0; j < N * P; ++j)
          row[j] += wt * wf[j];
      });
    else
      for_each_spread_row(sg, g, y, [&](size_t base, double w) {
        for (int b = 0; b < P; ++b)
          for (int a = 0; a < N; ++a)
            grid[N * (base + c.index[b]) + a] += T(w) * wf[N * b + a];
      });
  }
}

// The vector clones of spread_sources_into (target_clones takes no templates): one
// overload per component count and precision.
CAPSIM_VECTOR_CLONES void spread_sources(const SpreadGrid& sg, const ShearedLattice& g,
                                         const GridSources<3>& src,
                                         const std::vector<int>& members, double* grid) {
  spread_sources_into(sg, g, src, members, grid);
}

CAPSIM_VECTOR_CLONES void spread_sources(const SpreadGrid& sg, const ShearedLattice& g,
                                         const GridSources<3>& src,
                                         const std::vector<int>& members, float* grid) {
  spread_sources_into(sg, g, src, members, grid);
}

CAPSIM_VECTOR_CLONES void spread_sources(const SpreadGrid& sg, const ShearedLattice& g,
                                         const GridSources<6>& src,
                                         const std::vector<int>& members, double* grid) {
  spread_sources_into(sg, g, src, members, grid);
}

CAPSIM_VECTOR_CLONES void spread_sources(const SpreadGrid& sg, const ShearedLattice& g,
                                         const GridSources<6>& src,
                                         const std::vector<int>& members, float* grid) {
  spread_sources_into(sg, g, src, members, grid);
}

// The gathered grid values (N components, interleaved) at x: sum over the stencil of
// g(z_j - x) grid[j], with the rows summed as contiguous runs (as in spread_sources) and
// the column weights applied once at the end.
template <int N, class T>
CAPSIM_HD_INLINE void gather_point_from(const SpreadGrid& sg, const ShearedLattice& g,
                                        const T* grid, Vec3 x, double sum[N]) {
  const int P = sg.support;
  const SpreadColumn c = spread_column(sg, x);
  T acc[N * kMaxSpreadSupport] = {};
  if (c.contiguous)
    for_each_spread_row(sg, g, x, [&](size_t base, double w) {
      const T* row = grid + N * (base + c.index[0]);
      const T wt = T(w);
      for (int j = 0; j < N * P; ++j)
        acc[j] += wt * row[j];
    });
  else
    for_each_spread_row(sg, g, x, [&](size_t base, double w) {
      for (int b = 0; b < P; ++b)
        for (int a = 0; a < N; ++a)
          acc[N * b + a] += T(w) * grid[N * (base + c.index[b]) + a];
    });
  for (int a = 0; a < N; ++a)
    sum[a] = 0;
  for (int b = 0; b < P; ++b)
    for (int a = 0; a < N; ++a)
      sum[a] += c.weight[b] * double(acc[N * b + a]);
}

// The vector clones of gather_point_from, as those of spread_sources.
CAPSIM_VECTOR_CLONES void gather_point(const SpreadGrid& sg, const ShearedLattice& g,
                                       const double* grid, Vec3 x, double sum[3]) {
  gather_point_from<3>(sg, g, grid, x, sum);
}

CAPSIM_VECTOR_CLONES void gather_point(const SpreadGrid& sg, const ShearedLattice& g,
                                       const float* grid, Vec3 x, double sum[3]) {
  gather_point_from<3>(sg, g, grid, x, sum);
}

CAPSIM_VECTOR_CLONES void gather_point6(const SpreadGrid& sg, const ShearedLattice& g,
                                        const double* grid, Vec3 x, double sum[6]) {
  gather_point_from<6>(sg, g, grid, x, sum);
}

CAPSIM_VECTOR_CLONES void gather_point6(const SpreadGrid& sg, const ShearedLattice& g,
                                        const float* grid, Vec3 x, double sum[6]) {
  gather_point_from<6>(sg, g, grid, x, sum);
}

template <int N, class T>
void gather_values(const SpreadGrid& sg, const ShearedLattice& g, const T* grid, Vec3 x,
                   double sum[N]) {
  if constexpr (N == 3)
    gather_point(sg, g, grid, x, sum);
  else
    gather_point6(sg, g, grid, x, sum);
}

// The weights (spectral_mode_weight) of the modes i2 = 0 .. m2/2 of row (i0, i1).
CAPSIM_VECTOR_CLONES void row_weights(const ShearedLattice& g, const SpreadGrid& s,
                                      int i0, int i1, double xi, double c, double* w) {
  const int mh = s.m[2] / 2 + 1;
#pragma omp simd
  for (int i2 = 0; i2 < mh; ++i2)
    w[i2] = spectral_mode_weight(g, s, i0, i1, i2, xi, c);
}

// The same for the stresslet's multiplier (stresslet_mode_weight).
CAPSIM_VECTOR_CLONES void stresslet_row_weights(const ShearedLattice& g,
                                                const SpreadGrid& s, int i0, int i1,
                                                double xi, double c, double* w) {
  const int mh = s.m[2] / 2 + 1;
#pragma omp simd
  for (int i2 = 0; i2 < mh; ++i2)
    w[i2] = stresslet_mode_weight(g, s, i0, i1, i2, xi, c);
}

// The k-space kernels of the grid: In components spread, Out gathered; weights() fills
// a row's scalar weights, apply() maps a mode's In transformed components (real and
// imaginary parts) to its Out result components, in place.
struct StokesletModes {
  static constexpr int In = 3, Out = 3;
  static void weights(const ShearedLattice& g, const SpreadGrid& s, int i0, int i1,
                      double xi, double c, double* w) {
    row_weights(g, s, i0, i1, xi, c, w);
  }
  static void apply(Vec3 k, double w, double re[3], double im[3]) {
    project_spectral_mode(k, w, re, im);
  }
};

struct StressletModes {
  static constexpr int In = 6, Out = 3;
  static void weights(const ShearedLattice& g, const SpreadGrid& s, int i0, int i1,
                      double xi, double c, double* w) {
    stresslet_row_weights(g, s, i0, i1, xi, c, w);
  }
  static void apply(Vec3 k, double w, double re[6], double im[6]) {
    stresslet_spectral_mode(k, w, re, im);
  }
};

// The stresslet contracted with the normal vectors alone (three grids in, the six
// entries of a symmetric matrix out): the self matrices of the double layer.
struct StressletMatrixModes {
  static constexpr int In = 3, Out = 6;
  static void weights(const ShearedLattice& g, const SpreadGrid& s, int i0, int i1,
                      double xi, double c, double* w) {
    stresslet_row_weights(g, s, i0, i1, xi, c, w);
  }
  static void apply(Vec3 k, double w, double re[6], double im[6]) {
    stresslet_matrix_spectral_mode(k, w, re, im);
  }
};

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

SpectralParameters choose_stresslet_spectral_parameters(double L,
                                                        const EwaldParameters& ewald,
                                                        double tolerance) {
  // The stresslet's k-space kernel is one order of k above the stokeslet's (times k^2
  // of the screening), so the Gaussian's truncation and quadrature errors weigh more:
  // at the stokeslet's support the double layer's error was 1.1e-6 at tolerance 1e-6
  // (8 capsules, level 1, phi 0.3), with two more points 1.1e-7. Tolerance / 30 adds
  // two points; the grid, set by k_cut, stays.
  return choose_spectral_parameters(L, ewald, tolerance / 30.0);
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

namespace {

// The grid pipeline shared by the stokeslet and the stresslet: spread In components per
// source, FFT them, combine them mode by mode into Out components (Modes), FFT those
// back and gather them. The components are interleaved (grid[In j + a]): a stencil row
// is one run of memory for all of them, and one strided FFTW plan each way transforms
// them together, in double precision, or in single (p.single: FFTW's fftwf_ interface)
// where the tolerance leaves room for its rounding. The spectrum has C = max(In, Out)
// slots per mode: the forward plan writes the In transformed components into them, the
// modes are combined in place, and the backward plan reads the first Out (stride C) and
// writes them interleaved with stride Out into the real array, the layout gather_values
// reads. For the stokeslet (In = Out = C = 3) these are the plans of a single grid.
template <class Modes> class SpectralPipeline {
public:
  static constexpr int In = Modes::In, Out = Modes::Out, C = In > Out ? In : Out;

  SpectralPipeline(double L, double xi, const SpectralParameters& p)
      : L(L), xi(xi), p(p) {
    if (p.support > kMaxSpreadSupport)
      throw std::invalid_argument("spectral Ewald: support above the stencil limit");
    spread_grid = make_spread_grid(L, p.grid, p.support, xi, p.eta);
    n_real = grid_points(spread_grid);
    n_complex = spectrum_modes(spread_grid);
    // Planned once (FFTW_ESTIMATE leaves the arrays untouched) for the threads of the
    // run.
    const int* dims = p.grid;
    if (p.single) {
      static const bool threads_ready = fftwf_init_threads() != 0;
      if (threads_ready)
        fftwf_plan_with_nthreads(omp_get_max_threads());
      grid_f = fftwf_alloc_real(C * n_real);
      spectrum_f = fftwf_alloc_complex(C * n_complex);
      forward_f = fftwf_plan_many_dft_r2c(3, dims, In, grid_f, nullptr, In, 1, spectrum_f,
                                          nullptr, C, 1, FFTW_ESTIMATE);
      backward_f = fftwf_plan_many_dft_c2r(3, dims, Out, spectrum_f, nullptr, C, 1,
                                           grid_f, nullptr, Out, 1, FFTW_ESTIMATE);
      return;
    }
    static const bool threads_ready = fftw_init_threads() != 0;
    if (threads_ready)
      fftw_plan_with_nthreads(omp_get_max_threads());
    grid = fftw_alloc_real(C * n_real);
    spectrum = fftw_alloc_complex(C * n_complex);
    forward = fftw_plan_many_dft_r2c(3, dims, In, grid, nullptr, In, 1, spectrum, nullptr,
                                     C, 1, FFTW_ESTIMATE);
    backward = fftw_plan_many_dft_c2r(3, dims, Out, spectrum, nullptr, C, 1, grid,
                                      nullptr, Out, 1, FFTW_ESTIMATE);
  }

  ~SpectralPipeline() {
    if (p.single) {
      fftwf_destroy_plan(forward_f);
      fftwf_destroy_plan(backward_f);
      fftwf_free(grid_f);
      fftwf_free(spectrum_f);
      return;
    }
    fftw_destroy_plan(forward);
    fftw_destroy_plan(backward);
    fftw_free(grid);
    fftw_free(spectrum);
  }
  SpectralPipeline(const SpectralPipeline&) = delete;
  SpectralPipeline& operator=(const SpectralPipeline&) = delete;

  // sink(i, cell, v): the Out gathered values v at targets[i], to be scaled by the grid
  // cell V / (M_x M_y M_z).
  template <class Sink>
  void evaluate(const ShearedLattice& g, const GridSources<In>& src,
                const std::vector<Vec3>& targets, Sink sink, SpectralTimings* timings) {
    if (p.single)
      evaluate(
          g, src, targets, sink, grid_f, spectrum_f, [&] { fftwf_execute(forward_f); },
          [&] { fftwf_execute(backward_f); }, timings);
    else
      evaluate(
          g, src, targets, sink, grid, spectrum, [&] { fftw_execute(forward); },
          [&] { fftw_execute(backward); }, timings);
  }

private:
  double L, xi;
  SpectralParameters p;
  size_t n_real = 0, n_complex = 0;
  double* grid = nullptr;
  fftw_complex* spectrum = nullptr;
  fftw_plan forward = nullptr, backward = nullptr;
  float* grid_f = nullptr;
  fftwf_complex* spectrum_f = nullptr;
  fftwf_plan forward_f = nullptr, backward_f = nullptr;
  SpreadGrid spread_grid; // the Gaussian and its stencils (spectral_weights.hpp)

  template <class T>
  void spread(const ShearedLattice& g, const GridSources<In>& src, T* grid) const;
  template <class Complex>
  void scale_spectrum(const ShearedLattice& g, Complex* spectrum) const;
  template <class Sink, class T, class Complex, class Forward, class Backward>
  void evaluate(const ShearedLattice& g, const GridSources<In>& src,
                const std::vector<Vec3>& targets, Sink sink, T* grid, Complex* spectrum,
                Forward forward, Backward backward, SpectralTimings* timings);
};

// Spreads the sources to the grid in parallel without races: the sources are binned into
// slabs along the third grid direction, each at least P grid planes thick, so that a
// source's stencil touches only its own slab and the next; even slabs are spread
// concurrently, then odd ones. Each grid value receives its terms in the same order
// whatever the number of threads.
template <class Modes>
template <class T>
void SpectralPipeline<Modes>::spread(const ShearedLattice& g, const GridSources<In>& src,
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

// Multiplies the transformed grid by (8 pi / V)(V / (M_x M_y M_z)) times the k-space
// kernel with the remaining Gaussian (spectral_weights.hpp): per row the scalar weights
// in one vectorised loop (their exponentials were a twentieth of an evaluation at level
// 4 one mode at a time), then the tensor part (Modes::apply).
template <class Modes>
template <class Complex>
void SpectralPipeline<Modes>::scale_spectrum(const ShearedLattice& g,
                                             Complex* spectrum) const {
  const SpreadGrid& s = spread_grid;
  const int m1 = s.m[1], mh = s.m[2] / 2 + 1;
  const double c = 8.0 * kPi / double(grid_points(s));
#pragma omp parallel
  {
    std::vector<double> w(mh);
#pragma omp for schedule(static)
    for (int i0 = 0; i0 < s.m[0]; ++i0)
      for (int i1 = 0; i1 < m1; ++i1) {
        Modes::weights(g, s, i0, i1, xi, c, w.data());
        for (int i2 = 0; i2 < mh; ++i2) {
          const size_t k_index = (size_t(i0) * m1 + i1) * mh + i2;
          Complex* sk = spectrum + C * k_index;
          double re[C], im[C];
          for (int a = 0; a < In; ++a)
            re[a] = sk[a][0], im[a] = sk[a][1];
          Modes::apply(spectral_mode_vector(g, s, i0, i1, i2), w[i2], re, im);
          for (int a = 0; a < Out; ++a)
            sk[a][0] = re[a], sk[a][1] = im[a];
        }
      }
  }
}

// Spread, transform, scale, transform back and gather on the grid of precision T;
// forward() and backward() execute the matching FFTW plans.
template <class Modes>
template <class Sink, class T, class Complex, class Forward, class Backward>
void SpectralPipeline<Modes>::evaluate(const ShearedLattice& g,
                                       const GridSources<In>& src,
                                       const std::vector<Vec3>& targets, Sink sink,
                                       T* grid, Complex* spectrum, Forward forward,
                                       Backward backward, SpectralTimings* timings) {
  const double t0 = omp_get_wtime();
  const long n_grid = long(In * n_real);
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
  for (size_t i = 0; i < targets.size(); ++i) {
    double v[Out];
    gather_values<Out>(spread_grid, g, grid, targets[i], v);
    sink(i, cell, v);
  }
  if (timings) {
    timings->spread += t1 - t0;
    timings->fft += t2 - t1;
    timings->gather += omp_get_wtime() - t2;
  }
}

} // namespace

struct SpectralEwald::Impl {
  explicit Impl(double L, const EwaldParameters& ewald, const SpectralParameters& p)
      : pipeline(L, ewald.xi, p) {}
  SpectralPipeline<StokesletModes> pipeline;
};

SpectralEwald::SpectralEwald(double L, const EwaldParameters& ewald,
                             const SpectralParameters& p)
    : impl_(std::make_unique<Impl>(L, ewald, p)) {}

SpectralEwald::~SpectralEwald() = default;

void SpectralEwald::add_reciprocal(const ShearedLattice& g, const FarSources& src,
                                   const std::vector<Vec3>& targets, std::vector<Vec3>& u,
                                   SpectralTimings* timings) {
  const GridSources<3> grid_src{src.y, {&src.f[0], &src.f[1], &src.f[2]}};
  impl_->pipeline.evaluate(
      g, grid_src, targets,
      [&](size_t i, double cell, const double* v) {
        u[i] += cell * Vec3{v[0], v[1], v[2]};
      },
      timings);
}

struct SpectralStresslet::Impl {
  explicit Impl(double L, const EwaldParameters& ewald, const SpectralParameters& p)
      : L(L), xi(ewald.xi), p(p), pipeline(L, ewald.xi, p) {}
  double L, xi;
  SpectralParameters p;
  SpectralPipeline<StressletModes> pipeline;
};

SpectralStresslet::SpectralStresslet(double L, const EwaldParameters& ewald,
                                     const SpectralParameters& p)
    : impl_(std::make_unique<Impl>(L, ewald, p)) {}

SpectralStresslet::~SpectralStresslet() = default;

void SpectralStresslet::add_reciprocal(const ShearedLattice& g,
                                       const StressletSources& src,
                                       const std::vector<Vec3>& targets,
                                       std::vector<Vec3>& u, SpectralTimings* timings) {
  const GridSources<6> grid_src{
      src.y, {&src.d[0], &src.d[1], &src.d[2], &src.d[3], &src.d[4], &src.d[5]}};
  impl_->pipeline.evaluate(
      g, grid_src, targets,
      [&](size_t i, double cell, const double* v) {
        u[i] += cell * Vec3{v[0], v[1], v[2]};
      },
      timings);
}

// One grid pass per group: the reciprocal part is linear in the sources, so a group's
// sources alone on the grid give its own contribution. Its own pipeline (three grids in,
// six out), made for the call: the self matrices are set up once per geometry.
void SpectralStresslet::add_group_matrices(const ShearedLattice& g,
                                           const std::vector<Vec3>& y,
                                           const std::vector<Vec3>& a,
                                           size_t group_points,
                                           const std::vector<Vec3>& targets,
                                           size_t group_targets, std::vector<double>* m) {
  SpectralPipeline<StressletMatrixModes> pipeline(impl_->L, impl_->xi, impl_->p);
  const size_t groups = group_points ? y.size() / group_points : 0;
  std::vector<double> py[3], pa[3];
  std::vector<Vec3> x(group_targets);
  for (size_t c = 0; c < groups; ++c) {
    for (int d = 0; d < 3; ++d) {
      py[d].resize(group_points);
      pa[d].resize(group_points);
    }
    for (size_t j = 0; j < group_points; ++j) {
      const Vec3 yj = y[c * group_points + j], aj = a[c * group_points + j];
      py[0][j] = yj.x, py[1][j] = yj.y, py[2][j] = yj.z;
      pa[0][j] = aj.x, pa[1][j] = aj.y, pa[2][j] = aj.z;
    }
    for (size_t i = 0; i < group_targets; ++i)
      x[i] = targets[c * group_targets + i];
    const GridSources<3> src{py, {&pa[0], &pa[1], &pa[2]}};
    pipeline.evaluate(
        g, src, x,
        [&](size_t i, double cell, const double* v) {
          for (int e = 0; e < 6; ++e)
            m[e][c * group_targets + i] += cell * v[e];
        },
        nullptr);
  }
}

} // namespace capsim
