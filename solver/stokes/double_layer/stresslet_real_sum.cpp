#include "stokes/double_layer/stresslet_real_sum.hpp"

#include "common/vector_clones.hpp"
#include "stokes/double_layer/ewald_stresslet.hpp"

namespace capsim {
namespace {

CAPSIM_VECTOR_CLONES CAPSIM_FLATTEN Vec3
stresslet_real_sum_arrays(size_t n, const double* rx, const double* ry, const double* rz,
                          const double* const d[6], double xi) {
  double ux = 0, uy = 0, uz = 0;
#pragma omp simd reduction(+ : ux, uy, uz)
  for (size_t j = 0; j < n; ++j) {
    const double dj[6] = {d[0][j], d[1][j], d[2][j], d[3][j], d[4][j], d[5][j]};
    const Vec3 v = stresslet_real_apply_symmetric({rx[j], ry[j], rz[j]}, dj, xi);
    ux += v.x;
    uy += v.y;
    uz += v.z;
  }
  return {ux, uy, uz};
}

CAPSIM_VECTOR_CLONES CAPSIM_FLATTEN void
stresslet_real_matrix_sum_arrays(size_t n, const double* rx, const double* ry,
                                 const double* rz, const double* ax, const double* ay,
                                 const double* az, double xi, double m[6]) {
  double m0 = 0, m1 = 0, m2 = 0, m3 = 0, m4 = 0, m5 = 0;
#pragma omp simd reduction(+ : m0, m1, m2, m3, m4, m5)
  for (size_t j = 0; j < n; ++j) {
    double t[6] = {0, 0, 0, 0, 0, 0};
    stresslet_real_add_matrix({rx[j], ry[j], rz[j]}, {ax[j], ay[j], az[j]}, xi, t);
    m0 += t[0], m1 += t[1], m2 += t[2], m3 += t[3], m4 += t[4], m5 += t[5];
  }
  m[0] += m0, m[1] += m1, m[2] += m2, m[3] += m3, m[4] += m4, m[5] += m5;
}

} // namespace

void stresslet_real_matrix_sum(const PairBuffer& b, double xi, double m[6]) {
  stresslet_real_matrix_sum_arrays(b.n, b.rx.data(), b.ry.data(), b.rz.data(),
                                   b.fx.data(), b.fy.data(), b.fz.data(), xi, m);
}

Vec3 stresslet_real_sum(const StressletPairBuffer& b, double xi) {
  const double* const d[6] = {b.d[0].data(), b.d[1].data(), b.d[2].data(),
                              b.d[3].data(), b.d[4].data(), b.d[5].data()};
  return stresslet_real_sum_arrays(b.n, b.r[0].data(), b.r[1].data(), b.r[2].data(), d,
                                   xi);
}

} // namespace capsim
