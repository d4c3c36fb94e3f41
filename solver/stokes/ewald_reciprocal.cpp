#include "stokes/ewald_reciprocal.hpp"

#include "stokes/ewald_kernel.hpp"
#include "stokes/stokeslet.hpp"

#include <cmath>

namespace capsim {

namespace {

// (8 pi / V) sum_k w(k) (I - k k / k^2) Re[exp(i k . x) S(k)] at every node, with
// S(k) = C(k) - i S(k) given by `structure(k, C, S)`. The structure factors are computed
// first (in parallel over k), then each node sums over k: two parallel loops in all, not
// one per wave vector.
template <class Structure>
void add_reciprocal_sum(const ShearedLattice& g, const std::vector<Vec3>& x,
                        const EwaldParameters& p, Structure structure,
                        std::vector<Vec3>& u) {
  const double c = 8.0 * kPi / (g.L * g.L * g.L);
  const std::vector<Vec3> ks = wave_vectors(g, p.k_cut);
  std::vector<Vec3> cos_part(ks.size()), sin_part(ks.size());
#pragma omp parallel for schedule(static)
  for (size_t m = 0; m < ks.size(); ++m) {
    Vec3 sc, ss;
    structure(ks[m], sc, ss);
    cos_part[m] = c * ewald_recip_apply(ks[m], sc, p.xi);
    sin_part[m] = c * ewald_recip_apply(ks[m], ss, p.xi);
  }
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < x.size(); ++i)
    for (size_t m = 0; m < ks.size(); ++m) {
      double phase = dot(ks[m], x[i]);
      u[i] += std::cos(phase) * cos_part[m] + std::sin(phase) * sin_part[m];
    }
}

} // namespace

void ewald_reciprocal_direct(const ShearedLattice& g, const std::vector<Vec3>& x,
                             const FarSources& s, const EwaldParameters& p,
                             std::vector<Vec3>& u) {
  auto structure = [&](Vec3 k, Vec3& sc, Vec3& ss) {
    for (size_t j = 0; j < s.size(); ++j) {
      double phase = k.x * s.y[0][j] + k.y * s.y[1][j] + k.z * s.y[2][j];
      Vec3 f{s.f[0][j], s.f[1][j], s.f[2][j]};
      sc += std::cos(phase) * f;
      ss += std::sin(phase) * f;
    }
  };
  add_reciprocal_sum(g, x, p, structure, u);
}

void ewald_reciprocal_patches(const ShearedLattice& g, const std::vector<Vec3>& x,
                              const std::vector<PatchMoments>& patches,
                              const EwaldParameters& p, std::vector<Vec3>& u) {
  // cos(k.(x - c)) F + sin(k.(x - c)) D k, expanded in cos(k.x) and sin(k.x).
  auto structure = [&](Vec3 k, Vec3& sc, Vec3& ss) {
    for (const PatchMoments& m : patches) {
      const double phase = dot(k, m.centre), cs = std::cos(phase), sn = std::sin(phase);
      const Vec3 dk = m.dipole * k;
      sc += cs * m.force - sn * dk;
      ss += sn * m.force + cs * dk;
    }
  };
  add_reciprocal_sum(g, x, p, structure, u);
}

} // namespace capsim
