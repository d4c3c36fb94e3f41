#pragma once
// Spectral Ewald (Lindbo & Tornberg 2011) for the reciprocal-space part of the periodic
// Stokeslet sum, on the sheared lattice through fractional coordinates. The Gaussian
// factor exp(-k^2/(4 xi^2)) is split into exp(-sum_d (1 - eta_d) k_d^2/(4 xi^2)), applied
// on the grid, and two separable Gaussians g(r) = prod_d (2 xi^2/(pi eta_d))^(1/2)
// exp(-2 xi^2 r_d^2/eta_d) whose transform is exp(-sum_d eta_d k_d^2/(8 xi^2)):
//   1. spread H(z_j) = sum_g f_g g(z_j - y_g) to a uniform M_x M_y M_z grid in
//      fractional coordinates (z_j = A (j / M), A the lattice vectors), P grid points of
//      support in each direction;
//   2. FFT; multiply by the Stokes k-space kernel (8 pi / V) J^EII(k) with the remaining
//      Gaussian in place of exp(-k^2/(4 xi^2)); inverse FFT;
//   3. gather u(x) = (V / (M_x M_y M_z)) sum_j g(x - z_j) w_j.
// Cost O(N P^3 + M^3 log M) instead of O(N K). Only the sheared direction y needs 1.5
// times the wave numbers of the cut-off; x and z get 1.25 times (a margin against
// aliasing), so the grid is not a cube, and the Gaussian is separable with a width per
// direction, so its support stays P points in each. The stencil weights and the mode
// scaling are the host-device functions of spectral_weights.hpp, shared with the CUDA
// backend; this class is the CPU orchestration (parallel spreading, FFTW, gathering).
// SpectralStresslet (below) runs the periodic double layer's stresslet through the same
// pipeline (spectral_ewald.cpp: SpectralPipeline), with its own k-space kernel.
#include "stokes/kernels/periodic_stokeslet.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <memory>
#include <vector>

namespace capsim {

struct SpectralParameters {
  int grid[3] = {};    // M_d points along x, y (the sheared direction) and z (even)
  int support = 0;     // P grid points of Gaussian support per direction
  double eta[3] = {};  // Gaussian splitting per direction, 0 < eta_d < 1
  bool single = false; // grids and FFTs in single precision (ewald.precision)
};

// P from the tolerance (truncation and quadrature errors ~ exp(-pi P / 2)); M_d from the
// k-space cut-off of `ewald`: the grid must carry every |k| < k_cut of the sheared
// lattice, |n_x|, |n_z| <= k_cut L / 2 pi but |n_y| up to 1.5 times that, since k_y =
// 2 pi (n_y - s n_x) / L with |s| <= 1/2; x and z get a 25 % margin (spectral_ewald.cpp).
// eta_d = (2 w_d xi / m)^2 with w_d = P h_d / 2 and m = 0.976 sqrt(pi P): the same
// Gaussian in units of each direction's spacing.
SpectralParameters choose_spectral_parameters(double L, const EwaldParameters& ewald,
                                              double tolerance);

// The parameters for the stresslet (SpectralStresslet): those of the stokeslet at a
// thirtieth of the tolerance, two more points of support (spectral_ewald.cpp).
SpectralParameters choose_stresslet_spectral_parameters(double L,
                                                        const EwaldParameters& ewald,
                                                        double tolerance);

// xi for Spectral Ewald: the real-space sums cost ~ nodes x (points within r_cut), the
// grid ~ M^3 log M with M ~ xi L (spreading and gathering do not depend on xi); returns
// the xi of least modelled cost (docs/method.md, docs/performance.md).
double spectral_xi(double L, double tolerance, long nodes, long points);

struct SpectralTimings {
  double spread = 0, fft = 0, gather = 0;
};

class SpectralEwald {
public:
  SpectralEwald(double L, const EwaldParameters& ewald, const SpectralParameters& p);
  ~SpectralEwald();
  SpectralEwald(const SpectralEwald&) = delete;
  SpectralEwald& operator=(const SpectralEwald&) = delete;

  // Adds the reciprocal-space velocity (without the -1/(8 pi) factor) at the targets.
  void add_reciprocal(const ShearedLattice& lattice, const FarSources& sources,
                      const std::vector<Vec3>& targets, std::vector<Vec3>& u,
                      SpectralTimings* timings = nullptr);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The stresslet's sources: points y and the symmetric part of the source tensor u a^T
// (u the double-layer density, a the area-weighted normal at the point), entries xx, yy,
// zz, xy, xz, yz.
struct StressletSources {
  std::vector<double> y[3];
  std::vector<double> d[6];
  size_t size() const { return y[0].size(); }
};

// Spectral Ewald for the reciprocal part of the periodic stresslet (af Klinteberg &
// Tornberg 2014, "Fast Ewald summation for Stokesian particle suspensions", section 3),
// on the same grid pipeline as SpectralEwald: six source grids (the Fourier kernel
// sees only the symmetric part of u a^T), three result grids. Parameters from
// choose_stresslet_spectral_parameters.
class SpectralStresslet {
public:
  SpectralStresslet(double L, const EwaldParameters& ewald, const SpectralParameters& p);
  ~SpectralStresslet();
  SpectralStresslet(const SpectralStresslet&) = delete;
  SpectralStresslet& operator=(const SpectralStresslet&) = delete;

  // Adds (1/V) sum_{k != 0} phi(k) T^_ijk(k) D^_jk(k) exp(i k . x) at the targets, the
  // reciprocal part of sum_g u_gj T^per_ijk(x - y_g) a_gk (ewald_stresslet.hpp (3)).
  void add_reciprocal(const ShearedLattice& lattice, const StressletSources& sources,
                      const std::vector<Vec3>& targets, std::vector<Vec3>& u,
                      SpectralTimings* timings = nullptr);

  // Adds to m[e][i] (e: xx, yy, zz, xy, xz, yz) the reciprocal part of
  // sum_{g in group(i)} T^per_ijk(targets[i] - y_g) a_gk, the groups consecutive blocks
  // of group_points points (y, a) and group_targets targets (a capsule's rule points and
  // nodes: the double layer's self matrices). One grid pass per group, so O(groups)
  // FFTs: set up once per geometry.
  void add_group_matrices(const ShearedLattice& lattice, const std::vector<Vec3>& y,
                          const std::vector<Vec3>& a, size_t group_points,
                          const std::vector<Vec3>& targets, size_t group_targets,
                          std::vector<double>* m);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace capsim
