#include "stokes/ewald/ewald_reciprocal.hpp"
#include "stokes/ewald/ewald_setup.hpp"
#include "stokes/ewald/spectral_ewald.hpp"
#include "stokes/kernels/ewald_kernel.hpp"
#include "stokes/kernels/stokeslet.hpp"

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

// Single-precision grids (ewald.precision single) round the grid values to 24 bits:
// the reciprocal sum moves by about 1e-7 to 1e-6 of itself (FFT and stencil sums of a few
// hundred terms), far below the tolerances from which `auto` takes them (1e-5), while
// the truncation error stays that of the double grids.
TEST_CASE("spectral ewald: single-precision grids round, but keep the tolerance",
          "[spectral]") {
  const double L = 5.0, xi = 1.2;
  PointSet set(L, 300, 60, 11);
  const ShearedLattice g = make_sheared_lattice(L, 0.3);
  std::vector<Vec3> ref(set.targets.size());
  ewald_reciprocal_direct(g, set.targets, set.sources,
                          choose_ewald_parameters(L, 1e-14, xi), ref);
  for (double tol : {1e-3, 1e-5}) {
    const EwaldParameters e = choose_ewald_parameters(L, tol, xi);
    SpectralParameters p = choose_spectral_parameters(L, e, tol);
    std::vector<Vec3> u_double(set.targets.size()), u_single(set.targets.size());
    SpectralEwald(L, e, p).add_reciprocal(g, set.sources, set.targets, u_double);
    p.single = true;
    SpectralEwald(L, e, p).add_reciprocal(g, set.sources, set.targets, u_single);
    const double rounding = relative_error(u_single, u_double);
    INFO("tol " << tol << ": single against double " << rounding << ", against the "
                << "reference " << relative_error(u_single, ref));
    CHECK(rounding > 1e-9); // the single path ran: its rounding shows
    CHECK(rounding < 2e-6);
    CHECK(relative_error(u_single, ref) < 5 * tol);
  }
}

// The default precisions are automatic: single grids and real-space sum from
// kSinglePrecisionTolerance on, where their rounding (above; test_periodic.cpp) is at
// most a thirtieth of the tolerance; double below, so that a run at 1e-6 or tighter is
// computed as before.
TEST_CASE("spectral ewald: the default grids and real-space sum are single from 1e-5 "
          "on, double below",
          "[spectral]") {
  for (double tol : {1e-3, 1e-5, 9.9e-6, 1e-6, 1e-9}) {
    const EwaldOptions asked{EwaldMethod::spectral, tol};
    REQUIRE(asked.precision == Precision::automatic);
    REQUIRE(asked.real_space_precision == Precision::automatic);
    INFO("tolerance " << tol);
    const PeriodicBox box = make_periodic_box(5.0, asked, 1000, 3000);
    CHECK(box.grid.single == (tol >= 1e-5));
    CHECK(box.ewald.single_real == (tol >= 1e-5));
  }
}

TEST_CASE("ewald reciprocal: the half-space row sums equal the plain sum over all "
          "wave vectors",
          "[spectral]") {
  // The reference: (8 pi / V) sum_k J^EII(k) sum_j f_j cos(k . (x - y_j)) over every
  // wave vector, for point sources and for multipole patches (F and D k terms).
  const double L = 4.0, xi = 1.1;
  PointSet set(L, 40, 25, 5);
  std::vector<PatchMoments> patches(set.sources.size());
  for (size_t j = 0; j < patches.size(); ++j) {
    PatchMoments& m = patches[j];
    m.centre = {set.sources.y[0][j], set.sources.y[1][j], set.sources.y[2][j]};
    m.force = {set.sources.f[0][j], set.sources.f[1][j], set.sources.f[2][j]};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        m.dipole.m[a][b] = 0.1 * std::sin(3.0 * j + a - 2.0 * b);
  }
  const EwaldParameters p = choose_ewald_parameters(L, 1e-10, xi);
  const double c = 8.0 * kPi / (L * L * L);
  for (double strain : {0.0, 0.3, -0.5}) {
    ShearedLattice g = make_sheared_lattice(L, strain);
    std::vector<Vec3> ref_points(set.targets.size()), ref_patches(set.targets.size());
    for (const Vec3& k : wave_vectors(g, p.k_cut))
      for (size_t i = 0; i < set.targets.size(); ++i)
        for (const PatchMoments& m : patches) {
          const double phase = dot(k, set.targets[i] - m.centre);
          const Vec3 jf = c * ewald_recip_apply(k, m.force, p.xi);
          ref_points[i] += std::cos(phase) * jf;
          ref_patches[i] +=
              std::cos(phase) * jf +
              std::sin(phase) * c * ewald_recip_apply(k, m.dipole * k, p.xi);
        }
    std::vector<Vec3> u_points(set.targets.size()), u_patches(set.targets.size());
    ewald_reciprocal_direct(g, set.targets, set.sources, p, u_points);
    ewald_reciprocal_patches(g, set.targets, patches, p, u_patches);
    INFO("strain " << strain);
    CHECK(relative_error(u_points, ref_points) < 1e-13);
    CHECK(relative_error(u_patches, ref_patches) < 1e-13);
  }
}
