#include "stokes/ewald_reciprocal.hpp"
#include "stokes/spectral_ewald.hpp"

#include <catch2/catch.hpp>
#include <random>

using namespace capsim;

namespace {

// Random force-free point sources and random targets in a box of side L.
struct PointSet {
  FarSources sources;
  std::vector<Vec3> targets;
  PointSet(double L, int n_sources, int n_targets, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(0, L), force(-1, 1);
    Vec3 total;
    for (int k = 0; k < n_sources; ++k) {
      Vec3 f{force(rng), force(rng), force(rng)};
      if (k == n_sources - 1)
        f = -1.0 * total; // force-free, like a capsule
      total += f;
      Vec3 y{pos(rng), pos(rng), pos(rng)};
      for (int a = 0; a < 3; ++a) {
        sources.y[a].push_back((&y.x)[a]);
        sources.f[a].push_back((&f.x)[a]);
      }
    }
    for (int i = 0; i < n_targets; ++i)
      targets.push_back({pos(rng), pos(rng), pos(rng)});
  }
};

double relative_error(const std::vector<Vec3>& a, const std::vector<Vec3>& ref) {
  double e = 0, s = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    e += dot(a[i] - ref[i], a[i] - ref[i]);
    s += dot(ref[i], ref[i]);
  }
  return std::sqrt(e / s);
}

} // namespace

TEST_CASE("spectral ewald: error tracks the tolerance against direct k-space sums",
          "[spectral]") {
  const double L = 5.0, xi = 1.2;
  PointSet set(L, 300, 60, 11);
  for (double strain : {0.0, 0.5, -0.3}) {
    ShearedLattice g = make_sheared_lattice(L, strain);
    std::vector<Vec3> ref(set.targets.size());
    ewald_reciprocal_direct(g, set.targets, set.sources,
                            choose_ewald_parameters(L, 1e-14, xi), ref);
    for (double tol : {1e-4, 1e-6, 1e-8}) {
      EwaldParameters e = choose_ewald_parameters(L, tol, xi);
      SpectralParameters p = choose_spectral_parameters(L, e, tol);
      SpectralEwald se(L, e, p);
      std::vector<Vec3> u(set.targets.size());
      se.add_reciprocal(g, set.sources, set.targets, u);
      double err = relative_error(u, ref);
      INFO("strain " << strain << " tol " << tol << " grid " << p.grid[0] << " x "
                     << p.grid[1] << " x " << p.grid[2] << " support " << p.support
                     << " eta_x " << p.eta[0] << ": error " << err);
      CHECK(err < 5 * tol); // measured: 0.4x to 3x the tolerance
    }
  }
}
