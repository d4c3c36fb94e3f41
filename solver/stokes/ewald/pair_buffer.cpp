#include "stokes/ewald/pair_buffer.hpp"

#include "common/vector_clones.hpp"
#include "stokes/kernels/stokeslet.hpp"

namespace capsim {
namespace {

CAPSIM_VECTOR_CLONES Vec3 stokeslet_sum_arrays(size_t n, const double* rx,
                                               const double* ry, const double* rz,
                                               const double* fx, const double* fy,
                                               const double* fz) {
  double ux = 0, uy = 0, uz = 0;
#pragma omp simd reduction(+ : ux, uy, uz)
  for (size_t j = 0; j < n; ++j) {
    const Vec3 v = stokeslet_apply({rx[j], ry[j], rz[j]}, {fx[j], fy[j], fz[j]});
    ux += v.x;
    uy += v.y;
    uz += v.z;
  }
  return {ux, uy, uz};
}

} // namespace

Vec3 stokeslet_sum(const PairBuffer& b) {
  return stokeslet_sum_arrays(b.n, b.rx.data(), b.ry.data(), b.rz.data(), b.fx.data(),
                              b.fy.data(), b.fz.data());
}

} // namespace capsim
