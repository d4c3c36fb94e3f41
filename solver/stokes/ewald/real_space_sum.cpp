#include "stokes/ewald/real_space_sum.hpp"

#include "common/vector_clones.hpp"
#include "stokes/ewald/pair_buffer.hpp"
#include "stokes/kernels/ewald_kernel.hpp"

namespace capsim {

CAPSIM_VECTOR_CLONES Vec3 screened_sum(size_t n, const double* rx, const double* ry,
                                       const double* rz, const double* fx,
                                       const double* fy, const double* fz, double xi) {
  double ux = 0, uy = 0, uz = 0;
#pragma omp simd reduction(+ : ux, uy, uz)
  for (size_t j = 0; j < n; ++j) {
    const Vec3 v = ewald_real_apply({rx[j], ry[j], rz[j]}, {fx[j], fy[j], fz[j]}, xi);
    ux += v.x;
    uy += v.y;
    uz += v.z;
  }
  return {ux, uy, uz};
}

// The same in single precision, the terms summed in double: summed in float, a few
// hundred terms per target rounded the velocity by up to 2.5e-6 of itself, 16 times the
// rest of the single path's rounding (test_periodic.cpp), at no measurable saving.
CAPSIM_VECTOR_CLONES Vec3 screened_sum(size_t n, const float* rx, const float* ry,
                                       const float* rz, const float* fx, const float* fy,
                                       const float* fz, float xi) {
  double ux = 0, uy = 0, uz = 0;
#pragma omp simd reduction(+ : ux, uy, uz)
  for (size_t j = 0; j < n; ++j) {
    float a, b;
    ewald_real_factors(rx[j] * rx[j] + ry[j] * ry[j] + rz[j] * rz[j],
                       rx[j] * fx[j] + ry[j] * fy[j] + rz[j] * fz[j], xi, a, b);
    ux += double(a * fx[j] + b * rx[j]);
    uy += double(a * fy[j] + b * ry[j]);
    uz += double(a * fz[j] + b * rz[j]);
  }
  return {ux, uy, uz};
}

namespace {

std::vector<Vec3> point_positions(const FarSources& s) {
  std::vector<Vec3> y(s.size());
  for (size_t k = 0; k < s.size(); ++k)
    y[k] = {s.y[0][k], s.y[1][k], s.y[2][k]};
  return y;
}

// The sources in cell order, a structure each (a run of a few candidates touches fewer
// cache lines than in six arrays): wrapped positions (double, so that separations are
// exact before they are rounded) and loads (T).
template <class T> struct SortedSource {
  double x, y, z;
  T fx, fy, fz;
};
template <class T> struct SortedSources {
  std::vector<SortedSource<T>> p;
  SortedSources(const PeriodicCells& cells, const FarSources& s) {
    const int n = cells.size();
    p.resize(n);
    for (int j = 0; j < n; ++j) {
      const Vec3 w = cells.wrapped(j);
      const int k = cells.point(j);
      p[j] = {w.x, w.y, w.z, T(s.f[0][k]), T(s.f[1][k]), T(s.f[2][k])};
    }
  }
};

template <class T>
long add_real_space_sum_in(const ShearedLattice& lattice, const FarSources& s,
                           const std::vector<Vec3>& targets, const EwaldParameters& ewald,
                           std::vector<Vec3>& u) {
  // Cells half of r_cut wide: the sphere's cells then hold about 2.4 times its volume
  // (a third wide: 1.7 times), but there are fewer, longer runs; at level 3 the stage
  // took a tenth less (docs/performance.md).
  const PeriodicCells cells(lattice, ewald.r_cut, point_positions(s),
                            PeriodicCells::Index::table, 2.0);
  const SortedSources<T> src(cells, s);
  const double rc2 = ewald.r_cut * ewald.r_cut;
  const long n = long(targets.size());
  long pairs = 0;
#pragma omp parallel reduction(+ : pairs)
  {
    BasicPairBuffer<T> b; // the source images within r_cut of one target
    b.reserve(1024);
#pragma omp for schedule(dynamic, 16)
    for (long i = 0; i < n; ++i) {
      const Vec3 x = targets[i];
      cells.gather_within(x, rc2, b, [&](size_t m, int j, Vec3 xs) {
        const SortedSource<T>& q = src.p[j];
        const double rx = xs.x - q.x, ry = xs.y - q.y, rz = xs.z - q.z;
        b.rx[m] = T(rx), b.ry[m] = T(ry), b.rz[m] = T(rz);
        b.fx[m] = q.fx, b.fy[m] = q.fy, b.fz[m] = q.fz;
        return rx * rx + ry * ry + rz * rz;
      });
      u[i] += screened_sum(b.n, b.rx.data(), b.ry.data(), b.rz.data(), b.fx.data(),
                           b.fy.data(), b.fz.data(), T(ewald.xi));
      pairs += long(b.n);
    }
  }
  return pairs;
}

} // namespace

long add_real_space_sum(const ShearedLattice& lattice, const FarSources& s,
                        const std::vector<Vec3>& targets, const EwaldParameters& ewald,
                        std::vector<Vec3>& u) {
  return ewald.single_real ? add_real_space_sum_in<float>(lattice, s, targets, ewald, u)
                           : add_real_space_sum_in<double>(lattice, s, targets, ewald, u);
}

} // namespace capsim
