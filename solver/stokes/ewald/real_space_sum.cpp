#include "stokes/ewald/real_space_sum.hpp"

#include "common/vector_clones.hpp"
#include "stokes/kernels/ewald_kernel.hpp"
#include "stokes/ewald/pair_buffer.hpp"

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

namespace {

std::vector<Vec3> point_positions(const FarSources& s) {
  std::vector<Vec3> y(s.size());
  for (size_t k = 0; k < s.size(); ++k)
    y[k] = {s.y[0][k], s.y[1][k], s.y[2][k]};
  return y;
}

// The sources in cell order, structure of arrays: wrapped positions and loads.
struct SortedSources {
  std::vector<double> x, y, z, fx, fy, fz;
  SortedSources(const PeriodicCells& cells, const FarSources& s) {
    const int n = cells.size();
    for (auto* v : {&x, &y, &z, &fx, &fy, &fz})
      v->resize(n);
    for (int j = 0; j < n; ++j) {
      const Vec3 p = cells.wrapped(j);
      const int k = cells.point(j);
      x[j] = p.x, y[j] = p.y, z[j] = p.z;
      fx[j] = s.f[0][k], fy[j] = s.f[1][k], fz[j] = s.f[2][k];
    }
  }
};

} // namespace

long add_real_space_sum(const ShearedLattice& lattice, const FarSources& s,
                        const std::vector<Vec3>& targets, const EwaldParameters& ewald,
                        std::vector<Vec3>& u) {
  const PeriodicCells cells(lattice, ewald.r_cut, point_positions(s));
  const SortedSources src(cells, s);
  const double rc2 = ewald.r_cut * ewald.r_cut;
  const long n = long(targets.size());
  long pairs = 0;
#pragma omp parallel reduction(+ : pairs)
  {
    PairBuffer b; // the source images within r_cut of one target
    b.reserve(1024);
#pragma omp for schedule(dynamic, 16)
    for (long i = 0; i < n; ++i) {
      const Vec3 x = targets[i];
      b.n = 0;
      cells.for_neighbour_runs(x, [&](int begin, int end, Vec3 shift) {
        if (b.n + size_t(end - begin) > b.rx.size())
          b.reserve(2 * (b.n + size_t(end - begin)));
        const Vec3 xs = x - shift; // x relative to the unshifted images
        size_t m = b.n;
        // Branch-free compaction: every candidate is written, only those within r_cut
        // advance the count.
        for (int j = begin; j < end; ++j) {
          const double rx = xs.x - src.x[j], ry = xs.y - src.y[j], rz = xs.z - src.z[j];
          b.rx[m] = rx, b.ry[m] = ry, b.rz[m] = rz;
          b.fx[m] = src.fx[j], b.fy[m] = src.fy[j], b.fz[m] = src.fz[j];
          m += (rx * rx + ry * ry + rz * rz < rc2) ? 1 : 0;
        }
        b.n = m;
      });
      u[i] += screened_sum(b.n, b.rx.data(), b.ry.data(), b.rz.data(), b.fx.data(),
                           b.fy.data(), b.fz.data(), ewald.xi);
      pairs += long(b.n);
    }
  }
  return pairs;
}

} // namespace capsim
