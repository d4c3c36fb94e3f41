// The periodic double layer K (stokes/double_layer/periodic_double_layer.hpp): the Ewald
// split of the stresslet against xi, the free-space limit of a large box, the periodic
// Gauss identity with its volume term, and the lattice invariances. Tolerances are set
// from the errors measured at icosphere level 2 (quoted beside each check).
#include "mesh/surface_geometry.hpp"
#include "stokes/double_layer/double_layer.hpp"
#include "stokes/double_layer/periodic_double_layer.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

namespace {

const Vec3 kConstant{0.3, -1.0, 0.5};

// Capsules (level 2) of a tilted ellipsoidal shape centred at the given points, with a
// smooth density that is neither rigid nor divergence-free (a function of the position
// relative to the centre, so that a shifted capsule carries the same density).
struct Capsules {
  Icosphere mesh;
  std::vector<Vec3> x, u;
  explicit Capsules(const std::vector<Vec3>& centres, int level = 2)
      : mesh(make_icosphere(level)) {
    auto shape = testing::stretched(mesh.positions, 1.3, 0.8, 0.96, 0.5);
    for (const auto& c : centres)
      for (const Vec3& p : shape) {
        x.push_back(p + c);
        u.push_back({p.x + p.y * p.z, std::sin(p.y) + p.x * p.x, p.z * p.z * p.z});
      }
  }
  int count() const { return int(x.size()) / mesh.topology.num_nodes; }
  int nodes() const { return mesh.topology.num_nodes; }
  // spectral: the reciprocal sum by Spectral Ewald on the grid of the tolerance.
  // self_xi > 0 (with spectral): the self matrices' own split at that xi.
  PeriodicDoubleLayer op(double L, double strain, double tol, double xi = 0,
                         bool spectral = false, double self_xi = 0) const {
    const EwaldParameters ewald = choose_ewald_parameters(L, tol, xi);
    const SpectralParameters grid = choose_stresslet_spectral_parameters(L, ewald, tol);
    const EwaldParameters self = choose_ewald_parameters(L, tol, self_xi);
    const SpectralParameters self_grid =
        choose_stresslet_spectral_parameters(L, self, tol);
    const bool own = spectral && self_xi > 0;
    return PeriodicDoubleLayer(mesh.topology, count(), x, make_sheared_lattice(L, strain),
                               ewald, {}, spectral ? &grid : nullptr,
                               own ? &self : nullptr, own ? &self_grid : nullptr);
  }
  std::vector<Vec3> periodic(double L, double strain, double tol, double xi = 0,
                             bool spectral = false, double self_xi = 0) const {
    std::vector<Vec3> k;
    op(L, strain, tol, xi, spectral, self_xi).apply(u, k);
    return k;
  }
};

double max_error(const std::vector<Vec3>& a, size_t begin, size_t end, Vec3 expected) {
  double e = 0;
  for (size_t i = begin; i < end; ++i)
    e = std::max(e, norm(a[i] - expected));
  return e;
}

} // namespace

TEST_CASE("periodic double layer: the result does not depend on xi",
          "[periodic_double_layer]") {
  // Real and reciprocal sums share the 3-point rule points, and the near corrections and
  // the subtracted constant's identity do not involve xi: xi changes only the Ewald
  // truncation error.
  Capsules two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  const double L = 6.0, xi0 = 1.77245385 / L;
  const auto ref = two.periodic(L, 0.2, 1e-8, xi0);
  for (double factor : {2.0, 4.0}) {
    const double diff =
        testing::relative_difference(two.periodic(L, 0.2, 1e-8, factor * xi0), ref);
    INFO("xi = " << factor << " sqrt(pi)/L: " << diff);
    CHECK(diff < 1e-8);
  }
}

TEST_CASE("periodic double layer: a capsule in a large box sees the free-space K plus "
          "O(L^-3)",
          "[periodic_double_layer]") {
  // The images' field at the capsule: T^per - T is odd, so zero at r = 0, and its
  // gradient over the capsule is O(L^-3); the volume term V_c/V of the identity is
  // O(L^-3) as well.
  Capsules one({{0.3, -0.2, 0.1}});
  std::vector<Vec3> free;
  DoubleLayer(one.mesh.topology, 1, one.x, {}).apply(one.u, free);
  const double d15 = testing::relative_difference(one.periodic(15, 0.0, 1e-8), free);
  const double d30 = testing::relative_difference(one.periodic(30, 0.0, 1e-8), free);
  INFO("L = 15: " << d15 << ", L = 30: " << d30);
  CHECK(d30 < 1e-3);
  CHECK(d15 / d30 == Approx(8.0).margin(1.0));
}

TEST_CASE("periodic double layer: a constant density gives (1/2 - V_c/V) c on its own "
          "capsule and -(V_c/V) c outside it",
          "[periodic_double_layer]") {
  // The periodic Gauss identity (periodic_double_layer.hpp, (4)): the stresslet's
  // divergence has the background -8 pi/V of the omitted k = 0 term.
  Capsules two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  const int n = two.nodes();
  const double L = 5.0, V = L * L * L, xi = 3.0 * 1.77245385 / L;
  const PeriodicDoubleLayer k = two.op(L, 0.3, 1e-8, xi);
  std::vector<Vec3> c(2 * n, Vec3{}), v;
  for (int i = 0; i < n; ++i)
    c[i] = kConstant;
  k.apply(c, v);
  const double f = k.capsule_volume(0) / V; // 0.0258
  // Own capsule: by the subtraction, up to round-off of the cancelling sums.
  const double own = max_error(v, 0, n, (0.5 - f) * kConstant);
  // The other capsule: the 3-point rule of the smooth periodic kernel over the first.
  const double other = max_error(v, n, 2 * n, -f * kConstant);
  INFO("own " << own << ", other " << other << " (volume term " << f * norm(kConstant)
              << ")");
  CHECK(own < 1e-12);
  CHECK(other < 1e-3 * f * norm(kConstant));

  // Without subtraction (the polyhedron's principal value at the nodes, O(h) off c/2)
  // the periodic and free-space operators share the singular part, and differ
  // by the smooth remainder: -(V_c/V) c by the identity, up to quadrature error.
  Capsules one({{0.3, -0.2, 0.1}});
  const PeriodicDoubleLayer k1 = one.op(L, 0.3, 1e-8, xi);
  std::vector<Vec3> c1(n, kConstant), plain, free;
  k1.apply(c1, plain, false);
  DoubleLayer(one.mesh.topology, 1, one.x, {}).apply(c1, free, false);
  std::vector<Vec3> diff(n);
  for (int i = 0; i < n; ++i)
    diff[i] = plain[i] - free[i];
  const double f1 = k1.capsule_volume(0) / V;
  const double remainder = max_error(diff, 0, n, -f1 * kConstant);
  INFO("plain: remainder error " << remainder << " of " << f1 * norm(kConstant));
  CHECK(remainder < 1e-3 * f1 * norm(kConstant));
}

TEST_CASE("periodic double layer: a rigid rotation about the volume centroid is mapped "
          "to half itself, one about another point less the box's mean",
          "[periodic_double_layer]") {
  // By (4)'s derivation, 1/(8 pi) int_A u T^per n dA = u/2 - (1/V) int_V u dV on the
  // surface for a rigid motion u (its gradient is antisymmetric, T^per symmetric): for
  // u = Omega x (y - p) the volume term is V_c/V Omega x (c - p), c the volume centroid.
  // With the subtraction the free-space part of (u - u(x_i)) . T vanishes pointwise, and
  // what remains is the 3-point rule of the smooth remainder T^per - T.
  Capsules one({{0.3, -0.2, 0.1}});
  const int n = one.nodes();
  const double L = 5.0, V = L * L * L, xi = 3.0 * 1.77245385 / L;
  const PeriodicDoubleLayer k = one.op(L, 0.3, 1e-8, xi);
  const Vec3 omega{0.2, 0.7, -0.4};
  const Vec3 c = volume_centroid(one.mesh.topology, one.x.data());
  const double f = k.capsule_volume(0) / V;
  double err[2], scale = 0;
  const Vec3 pivots[2] = {c, c + Vec3{0.5, -0.3, 0.2}};
  for (int j = 0; j < 2; ++j) {
    std::vector<Vec3> u(n), v;
    for (int i = 0; i < n; ++i)
      u[i] = cross(omega, one.x[i] - pivots[j]);
    k.apply(u, v);
    const Vec3 mean = f * cross(omega, c - pivots[j]);
    err[j] = 0;
    for (int i = 0; i < n; ++i) {
      err[j] = std::max(err[j], norm(v[i] - (0.5 * u[i] - mean)));
      scale = std::max(scale, norm(u[i]));
    }
  }
  INFO("about the centroid " << err[0] << ", about another point " << err[1]
                             << " (volume term " << f * norm(cross(omega, pivots[1] - c))
                             << ")");
  CHECK(err[0] < 1e-6 * scale);
  CHECK(err[1] < 1e-6 * scale);
}

TEST_CASE("periodic double layer: lattice images and strain periods give the same K",
          "[periodic_double_layer]") {
  const double L = 6.0, xi = 2.0 * 1.77245385 / L; // exact invariances: any accuracy
  const ShearedLattice g = make_sheared_lattice(L, 0.2);
  Capsules a({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  Capsules b({{0.2, 0.1, 0.0}, Vec3{2.9, 2.4, -0.3} + lattice_point(g, 1, -1, 2)});
  Capsules c({Vec3{0.2, 0.1, 0.0} + lattice_point(g, -1, 1, 0), {2.9, 2.4, -0.3}});
  const auto ka = a.periodic(L, 0.2, 1e-6, xi);
  const double db = testing::relative_difference(b.periodic(L, 0.2, 1e-6, xi), ka);
  const double dc = testing::relative_difference(c.periodic(L, 0.2, 1e-6, xi), ka);
  const double ds = testing::relative_difference(a.periodic(L, 1.2, 1e-6, xi), ka);
  INFO("shifted second " << db << ", shifted first " << dc << ", strain + 1 " << ds);
  CHECK(db < 1e-10);
  CHECK(dc < 1e-10);
  CHECK(ds < 1e-10);
}

TEST_CASE("periodic double layer: Spectral Ewald matches the direct reciprocal sum",
          "[periodic_double_layer]") {
  // Same xi and cut-offs, so the two differ by the grid's errors and by the modes beyond
  // k_cut that the grid keeps (both of the order of the tolerance). Three capsules, one
  // across the box boundary, and a sheared lattice (the stresslet is odd in k, so a
  // wrong sign of a wave vector shows here, unlike for the stokeslet).
  // xi = 3 sqrt(pi)/L puts most of the far field into the reciprocal sums (apply's and
  // the self matrices').
  Capsules three({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}, {-2.1, 2.8, 2.6}}, 1);
  const double L = 6.0, xi = 3.0 * 1.77245385 / L;
  for (double strain : {0.0, 0.3}) {
    for (double tol : {1e-6, 1e-9}) {
      const auto direct = three.periodic(L, strain, tol, xi);
      const auto spectral = three.periodic(L, strain, tol, xi, true);
      const double diff = testing::relative_difference(spectral, direct);
      INFO("strain " << strain << ", tolerance " << tol << ": " << diff);
      CHECK(diff < tol);
    }
  }
}

TEST_CASE("periodic double layer: the self matrices' own split changes nothing but the "
          "truncation",
          "[periodic_double_layer]") {
  // The self matrices are the same sums at another xi: only the Ewald truncation and
  // grid errors, of the order of the tolerance, change.
  Capsules two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  const double L = 6.0, xi = 2 * 1.77245385 / L, tol = 1e-7;
  const auto ref = two.periodic(L, 0.3, tol, xi, true);
  for (double factor : {0.5, 0.33}) {
    const double diff = testing::relative_difference(
        two.periodic(L, 0.3, tol, xi, true, factor * xi), ref);
    INFO("self xi = " << factor << " xi: " << diff);
    CHECK(diff > 0); // the own split is taken
    CHECK(diff < tol);
  }
}

TEST_CASE("periodic double layer: with Spectral Ewald the result does not depend on xi",
          "[periodic_double_layer]") {
  // xi moves work between the real-space sum and the grid; only the Ewald truncation
  // and grid errors, of the order of the tolerance, change.
  Capsules two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  const double L = 6.0, xi0 = 1.77245385 / L, tol = 1e-7;
  const auto ref = two.periodic(L, 0.3, tol, xi0, true);
  for (double factor : {2.0, 4.0}) {
    const double diff =
        testing::relative_difference(two.periodic(L, 0.3, tol, factor * xi0, true), ref);
    INFO("xi = " << factor << " sqrt(pi)/L: " << diff);
    CHECK(diff < tol);
  }
}
