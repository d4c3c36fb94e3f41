// Spectral Ewald on the device: spreading, scaling of the transformed grid and gathering,
// around stokes/ewald/spectral_weights.hpp (the FFTs themselves are cuFFT, device_fft.cpp).
#include "cuda/device_kernels.hpp"
#include "cuda/launch.cuh"

namespace capsim::cuda {
namespace {

// One thread per source; stencils of nearby sources overlap, hence atomics (native for
// doubles from sm_60). The summation order varies from run to run at rounding level.
__global__ void spread_kernel(SpreadGrid s, ShearedLattice g, int count, const Vec3* y,
                              const Vec3* f, double* grid) {
  const int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= count)
    return;
  const size_t n_real = grid_points(s);
  const Vec3 fk = f[k];
  for_each_spread_point(s, g, y[k], [&](size_t j, double w) {
    atomicAdd(grid + j, w * fk.x);
    atomicAdd(grid + n_real + j, w * fk.y);
    atomicAdd(grid + 2 * n_real + j, w * fk.z);
  });
}

// One thread per mode of the half spectrum.
__global__ void scale_spectrum_kernel(ShearedLattice g, SpreadGrid s, double xi, double c,
                                      double* spectrum) {
  const int mh = s.m[2] / 2 + 1;
  const size_t n_complex = spectrum_modes(s);
  const size_t k = size_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (k >= n_complex)
    return;
  const int i2 = int(k % mh), i1 = int(k / mh % s.m[1]), i0 = int(k / mh / s.m[1]);
  double re[3], im[3];
  for (int a = 0; a < 3; ++a) {
    re[a] = spectrum[2 * (a * n_complex + k)];
    im[a] = spectrum[2 * (a * n_complex + k) + 1];
  }
  scale_spectral_mode(g, s, i0, i1, i2, xi, c, re, im);
  for (int a = 0; a < 3; ++a) {
    spectrum[2 * (a * n_complex + k)] = re[a];
    spectrum[2 * (a * n_complex + k) + 1] = im[a];
  }
}

// One thread per target: a read-only stencil, no atomics.
__global__ void gather_kernel(SpreadGrid s, ShearedLattice g, int n, const Vec3* x,
                              const double* grid, double cell, Vec3* u) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n)
    return;
  const size_t n_real = grid_points(s);
  Vec3 sum;
  for_each_spread_point(s, g, x[i], [&](size_t j, double w) {
    sum += w * Vec3{grid[j], grid[n_real + j], grid[2 * n_real + j]};
  });
  u[i] += cell * sum;
}

} // namespace

void spread(const SpreadGrid& s, const ShearedLattice& g, int count, const Vec3* y,
            const Vec3* f, double* grid) {
  CAPSIM_LAUNCH(spread_kernel, blocks_for(count), kBlock)(s, g, count, y, f, grid);
  check_launch("spread");
}

void scale_spectrum(const ShearedLattice& g, const SpreadGrid& s, double xi, double c,
                    double* spectrum) {
  const long modes = long(spectrum_modes(s));
  CAPSIM_LAUNCH(scale_spectrum_kernel, blocks_for(modes), kBlock)(g, s, xi, c, spectrum);
  check_launch("scale_spectrum");
}

void gather(const SpreadGrid& s, const ShearedLattice& g, int n, const Vec3* x,
            const double* grid, double cell, Vec3* u) {
  CAPSIM_LAUNCH(gather_kernel, blocks_for(n), kBlock)(s, g, n, x, grid, cell, u);
  check_launch("gather");
}

} // namespace capsim::cuda
