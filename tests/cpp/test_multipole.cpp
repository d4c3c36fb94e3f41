#include "membrane/membrane_forces.hpp"
#include "stokes/ewald/multipole_patches.hpp"
#include "stokes/kernels/stokeslet.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

namespace {

// A capsule-like load: the membrane load of a tilted ellipsoidal deformation of the
// level-3 icosphere (force-free, with a stresslet like a capsule in shear). `pear` adds a
// deformation that is not symmetric under x -> -x: without it the load is
// centrosymmetric, its quadrupole vanishes, and the patch error decays faster than 1/r.
struct DeformedCapsule {
  Icosphere mesh = make_icosphere(3);
  std::vector<Vec3> x, q;
  explicit DeformedCapsule(double pear) {
    x = testing::stretched(mesh.positions, 1.4, 0.75, 0.95, 0.45);
    for (auto& p : x)
      p += Vec3{pear * p.y * p.y, pear * p.x * p.z, 0.0};
    Membrane m(mesh.topology, mesh.positions.data(), 1.0);
    std::vector<Vec3> grad;
    m.energy_gradient(x.data(), grad);
    m.nodal_load(x.data(), grad, LoadMapping::lumped, q);
  }
  // Relative error of the P-patch velocity (patch_level: -1 for P = 1) at distance r
  // along the unit direction e.
  double error(int patch_level, double r, Vec3 e) const {
    auto patches = patch_moments(mesh.topology, 3, patch_level, x.data(), q.data());
    Vec3 p = r * e;
    Vec3 ref = surface_velocity_at(p, mesh.topology, x.data(), q.data());
    return norm(patch_velocity(p, patches) - ref) / norm(ref);
  }
};

} // namespace

TEST_CASE("multipole: the dipole term is the first-order Taylor term of the Stokeslet",
          "[multipole]") {
  const Vec3 r{1.3, -0.7, 2.1}, dy{1e-4, -2e-4, 0.5e-4}, q{0.3, 1.0, -0.6};
  Mat3 d; // D_jk = q_j dy_k for a point load at c + dy
  const double qa[3] = {q.x, q.y, q.z}, da[3] = {dy.x, dy.y, dy.z};
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k)
      d.m[j][k] = qa[j] * da[k];
  Vec3 exact = stokeslet_apply(r - dy, q);
  Vec3 first = stokeslet_apply(r, q) - stokeslet_gradient_contract(r, d);
  CHECK(norm(exact - first) < 1e-7);                 // O(|dy|^2)
  CHECK(norm(exact - stokeslet_apply(r, q)) > 1e-5); // the first-order term matters
}

TEST_CASE(
    "multipole: patch errors decay as 1/r and P = 80 / 20 meet 1e-2 at r/a = 3 / 10",
    "[multipole]") {
  DeformedCapsule c(0.15), symmetric(0.0);
  const Vec3 dirs[3] = {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}}; // flow, vorticity, gradient
  auto mean_error = [&](int level, double r, const DeformedCapsule& c) {
    double s = 0;
    for (const auto& e : dirs)
      s += c.error(level, r, e) / 3.0;
    return s;
  };
  CHECK(mean_error(1, 3.0, c) < 1e-2);  // P = 80 (paper eq. 3.12)
  CHECK(mean_error(0, 10.0, c) < 1e-2); // P = 20
  for (int level : {-1, 0, 1}) {
    // Far enough that the leading (quadrupole) error dominates the next one.
    double e20 = mean_error(level, 20.0, c), e40 = mean_error(level, 40.0, c);
    double s10 = mean_error(level, 10.0, symmetric),
           s20 = mean_error(level, 20.0, symmetric);
    INFO("patch level " << level << ": " << e20 << " " << e40 << "; symmetric " << s10
                        << " " << s20);
    CHECK(e40 / e20 == Approx(0.5).margin(0.1));   // O(1/r): the quadrupole error
    CHECK(s20 / s10 == Approx(0.25).margin(0.05)); // O(1/r^2): no quadrupole
  }
  // More patches, smaller error.
  CHECK(mean_error(2, 4.0, c) < mean_error(1, 4.0, c));
  CHECK(mean_error(1, 4.0, c) < mean_error(0, 4.0, c));
  CHECK(mean_error(0, 4.0, c) < mean_error(-1, 4.0, c));
}
