#include "membrane/membrane_forces.hpp"
#include "stokes/single_layer/periodic_single_layer.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>
#include <memory>

using namespace capsim;

namespace {

// Capsules (level 2) with the membrane load of a tilted ellipsoidal deformation, centred
// at the given points.
struct Suspension {
  Icosphere mesh;
  std::vector<Vec3> x, q;
  explicit Suspension(const std::vector<Vec3>& centres, int level = 2)
      : mesh(make_icosphere(level)) {
    auto shape = testing::stretched(mesh.positions, 1.3, 0.8, 0.96, 0.5);
    Membrane m(mesh.topology, mesh.positions.data(), 1.0);
    std::vector<Vec3> grad, qc;
    m.energy_gradient(shape.data(), grad);
    m.nodal_load(shape.data(), grad, LoadMapping::lumped, qc);
    for (const auto& c : centres)
      for (int i = 0; i < mesh.topology.num_nodes; ++i) {
        x.push_back(shape[i] + c);
        q.push_back(qc[i]);
      }
  }
  int count() const { return int(x.size()) / mesh.topology.num_nodes; }
  std::vector<Vec3> periodic(double L, double strain, double tol, double xi = 0,
                             bool spectral = false, int patch_level = -1,
                             bool single_real = false) const {
    std::vector<Vec3> u;
    EwaldParameters e = choose_ewald_parameters(L, tol, xi);
    e.single_real = single_real;
    std::unique_ptr<SpectralEwald> se;
    if (spectral)
      se = std::make_unique<SpectralEwald>(L, e, choose_spectral_parameters(L, e, tol));
    periodic_single_layer_velocity(mesh.topology, count(), x, q,
                                   make_sheared_lattice(L, strain), e, {}, u,
                                   {se.get(), patch_level});
    return u;
  }
};

} // namespace

TEST_CASE("periodic: a capsule in a large box sees the free-space flow plus O(L^-3)",
          "[periodic]") {
  Suspension one({{0.3, -0.2, 0.1}});
  std::vector<Vec3> free;
  single_layer_velocity(one.mesh.topology, 1, one.x, one.q, {}, free);
  double d15 = testing::relative_difference(one.periodic(15, 0.0, 1e-8), free);
  double d30 = testing::relative_difference(one.periodic(30, 0.0, 1e-8), free);
  INFO("L = 15: " << d15 << ", L = 30: " << d30);
  CHECK(d30 < 1e-3);
  CHECK(d15 / d30 == Approx(8.0).margin(2.5));
}

TEST_CASE("periodic: the velocity does not depend on xi", "[periodic]") {
  // The real-space and reciprocal sums share the 3-point rule points and the near
  // correction is free-space only, so xi changes nothing but the Ewald truncation error:
  // over xi h = 0.09 .. 0.7 (level 2, h ~ 0.3) the velocities agree to the 1e-8
  // tolerance.
  Suspension two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  const double L = 6.0, xi0 = 1.77245385 / L;
  auto ref = two.periodic(L, 0.2, 1e-8, 1.0 * xi0);
  for (double factor : {3.0, 8.0}) {
    const double diff =
        testing::relative_difference(two.periodic(L, 0.2, 1e-8, factor * xi0), ref);
    INFO("xi = " << factor << " sqrt(pi)/L: " << diff);
    CHECK(diff < 1e-8); // measured 7.3e-10 and 7.4e-10
  }
}

TEST_CASE("periodic: images and strain periods give identical velocities", "[periodic]") {
  const double L = 6.0;
  Suspension a({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  Suspension b(
      {{0.2, 0.1, 0.0},
       Vec3{2.9, 2.4, -0.3} + lattice_point(make_sheared_lattice(L, 0.2), 1, -1, 2)});
  const double xi = 2.0 * 1.77245385 / L; // exact invariances: any accuracy will do
  auto ua = a.periodic(L, 0.2, 1e-6, xi);
  CHECK(testing::relative_difference(b.periodic(L, 0.2, 1e-6, xi), ua) < 1e-10);
  CHECK(testing::relative_difference(a.periodic(L, 1.2, 1e-6, xi), ua) < 1e-10);
}

TEST_CASE("periodic: Spectral Ewald matches the direct reciprocal sum", "[periodic]") {
  Suspension two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  for (double strain : {0.0, 0.45}) {
    auto direct = two.periodic(10.0, strain, 1e-8, 1.2);
    auto spectral = two.periodic(10.0, strain, 1e-8, 1.2, true);
    CHECK(testing::relative_difference(spectral, direct) <
          1e-7); // measured 2.2e-8, 2.4e-8
  }
}

TEST_CASE("periodic: with Spectral Ewald a large xi (short real space) changes nothing",
          "[periodic]") {
  // Level 3 (h = 0.15), L = 12, tolerance 1e-6: xi = 5 (xi h = 0.75, r_cut 0.8) against
  // xi = 0.8 (r_cut 5.1). Only the Ewald truncation and grid errors differ.
  Suspension two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}}, 3);
  const double L = 12.0;
  auto short_range = two.periodic(L, 0.3, 1e-6, 5.0, true);
  auto reference = two.periodic(L, 0.3, 1e-6, 0.8, true);
  const double diff = testing::relative_difference(short_range, reference);
  INFO("relative difference " << diff);
  CHECK(diff < 1e-5);
}

// The real-space sum in single precision (ewald.real_space_precision) rounds separations,
// loads and kernel to 24 bits, and sums the terms in double: the velocity moves by about
// 1e-7 of itself (the largest difference over the nodes against the largest velocity), a
// hundredth of the tolerances from which `auto` takes it.
TEST_CASE("periodic: the real-space sum in single precision rounds, but keeps the "
          "tolerance",
          "[periodic]") {
  Suspension two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  const double L = 6.0, xi = 2.0; // r_cut 1.2 and 1.8: 60 and 200 pairs per target
  const auto reference = two.periodic(L, 0.3, 1e-10, xi, true);
  for (double tol : {1e-3, 1e-5}) {
    const auto dbl = two.periodic(L, 0.3, tol, xi, true);
    const auto sgl = two.periodic(L, 0.3, tol, xi, true, -1, true);
    const double rounding = testing::relative_difference(sgl, dbl);
    INFO("tol " << tol << ": single against double " << rounding << ", against the "
                << "reference " << testing::relative_difference(sgl, reference));
    CHECK(rounding > 1e-9); // the single path ran: its rounding shows
    CHECK(rounding < 1e-6); // measured 1.0e-7 at both
    CHECK(testing::relative_difference(sgl, reference) < tol);
  }
}

TEST_CASE("periodic: method patches converges to the fine sum at second order in the "
          "patch size",
          "[periodic]") {
  // Only the reciprocal sum is coarse-grained; its kernel is smooth on the scale 1/xi, so
  // the first neglected term (the patch quadrupole) makes the error O((xi d)^2) for
  // patches of diameter d, which halves with each patch level.
  Suspension two({{0.2, 0.1, 0.0}, {2.9, 2.4, -0.3}});
  const double L = 6.0, xi = 1.2;
  auto fine = two.periodic(L, 0.3, 1e-8, xi);
  double err[3];
  for (int level = 0; level <= 2; ++level)
    err[level] =
        testing::relative_difference(two.periodic(L, 0.3, 1e-8, xi, false, level), fine);
  INFO("P = 20, 80, 320: " << err[0] << ", " << err[1] << ", " << err[2]);
  CHECK(err[1] < 1e-2); // the paper's bound for P = 80 (eq. 3.12)
  CHECK(err[0] / err[1] > 3.0);
  CHECK(err[1] / err[2] > 3.0);
}
