#include "stokes/ewald_reciprocal.hpp"

#include "stokes/ewald_kernel.hpp"
#include "stokes/stokeslet.hpp"

#include <cmath>

namespace capsim {

// (8 pi / V) sum_k w(k) (I - k k / k^2) Re[exp(i k . x) S(k)] at every node. The
// structure factors are computed first (in parallel over k), then each node sums over k:
// two parallel loops in all, not one per wave vector.
void ewald_reciprocal_direct(const ShearedLattice& g, const std::vector<Vec3>& x,
                             const FarSources& s, const EwaldParameters& p,
                             std::vector<Vec3>& u) {
  const double c = 8.0 * kPi / (g.L * g.L * g.L);
  const std::vector<Vec3> ks = wave_vectors(g, p.k_cut);
  std::vector<Vec3> cos_part(ks.size()), sin_part(ks.size());
#pragma omp parallel for schedule(static)
  for (size_t m = 0; m < ks.size(); ++m) {
    const Vec3 k = ks[m];
    Vec3 sc, ss;
    for (size_t j = 0; j < s.size(); ++j) {
      double phase = k.x * s.y[0][j] + k.y * s.y[1][j] + k.z * s.y[2][j];
      Vec3 f{s.f[0][j], s.f[1][j], s.f[2][j]};
      sc += std::cos(phase) * f;
      ss += std::sin(phase) * f;
    }
    cos_part[m] = c * ewald_recip_apply(k, sc, p.xi);
    sin_part[m] = c * ewald_recip_apply(k, ss, p.xi);
  }
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < x.size(); ++i)
    for (size_t m = 0; m < ks.size(); ++m) {
      double phase = dot(ks[m], x[i]);
      u[i] += std::cos(phase) * cos_part[m] + std::sin(phase) * sin_part[m];
    }
}

} // namespace capsim
