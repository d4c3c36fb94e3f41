#include "membrane/membrane_forces.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

namespace {

// The unit sphere's nodes moved radially to r = 1 + eps P2(z).
std::vector<Vec3> p2_shape(const std::vector<Vec3>& sphere, double eps) {
  std::vector<Vec3> x;
  for (const Vec3& p : sphere)
    x.push_back((1 + eps * 0.5 * (3 * p.z * p.z - 1)) * p);
  return x;
}

} // namespace

TEST_CASE("bending: every edge is one hinge, its triangles outward on both sides",
          "[membrane][bending]") {
  Icosphere s = make_icosphere(2);
  auto hinges = make_hinges(s.topology);
  CHECK(hinges.size() == 3 * s.topology.triangles.size() / 2);
  for (const Hinge& h : hinges) {
    double theta = dihedral_angle(s.positions[h.a], s.positions[h.b], s.positions[h.c],
                                  s.positions[h.d]);
    CHECK(theta > 0.05); // convex, about the edge length (0.19) at level 2
    CHECK(theta < 0.3);
  }
}

TEST_CASE("bending: forces are the exact gradient of the hinge energy",
          "[membrane][bending]") {
  Icosphere s = make_icosphere(2);
  Membrane m(s.topology, s.positions.data(), 0.0, 0.3); // bending only
  auto x =
      testing::perturbed(testing::stretched(s.positions, 1.3, 0.9, 1.1, 0.4), 0.02, 11);
  std::vector<Vec3> grad;
  m.energy_gradient(x.data(), grad);
  auto [worst, scale] =
      testing::gradient_check([&](const Vec3* p) { return m.energy(p); }, x, grad, 5);
  CHECK(scale > 1e-3);
  CHECK(worst / scale < 1e-7);
}

TEST_CASE("bending: the reference sphere, moved, turned or inflated, carries no load",
          "[membrane][bending]") {
  Icosphere s = make_icosphere(3);
  Membrane m(s.topology, s.positions.data(), 0.0, 1.0);
  auto x = testing::stretched(s.positions, 1.3, 1.3, 1.3, 0.8);
  for (auto& p : x)
    p += Vec3{0.3, -2, 5};
  std::vector<Vec3> grad;
  CHECK(m.energy_gradient(x.data(), grad) == Approx(0).margin(1e-20));
  for (const auto& g : grad)
    CHECK(norm(g) < 1e-10); // rounding of theta - theta0 (1e-16) times kb w / h
}

// The hinge sum of a smooth shape must not depend on the mesh level: that is what makes
// one kb mean the same at every level. r = 1 + eps P2(cos theta) changes curvature and
// stretch unevenly (bending.hpp); the icosphere's triangles vary by about 20 % in size
// and shape, so the levels agree to a few per cent, better as the mesh refines.
TEST_CASE("bending: the energy of a P2 shape mode is the same at every mesh level",
          "[membrane][bending]") {
  const double eps = 1e-3;
  std::vector<double> energy;
  for (int level : {2, 3, 4}) {
    Icosphere s = make_icosphere(level);
    Membrane m(s.topology, s.positions.data(), 0.0, 1.0);
    auto x = p2_shape(s.positions, eps);
    energy.push_back(m.energy(x.data()) / (eps * eps));
  }
  INFO("E / eps^2 at levels 2, 3, 4: " << energy[0] << " " << energy[1] << " "
                                       << energy[2]);
  CHECK(std::abs(energy[1] / energy[0] - 1) < 0.08);
  CHECK(std::abs(energy[2] / energy[1] - 1) < 0.03);
}

// For a change of curvature alike in every direction the hinge sum is the Helfrich
// energy (kb / 2) int (2 dk)^2 dA. The reference sphere against a flat sheet has dk = 1
// everywhere: sum_e w_e theta0_e^2 = int 4 dA = 16 pi.
TEST_CASE("bending: the weights give the Helfrich energy of uniform curvature",
          "[membrane][bending]") {
  for (int level : {3, 4}) {
    Icosphere s = make_icosphere(level);
    double sum = 0;
    for (const Hinge& h : make_hinges(s.topology)) {
      HingeReference r = make_hinge_reference(s.positions[h.a], s.positions[h.b],
                                              s.positions[h.c], s.positions[h.d]);
      sum += r.weight * r.theta0 * r.theta0;
    }
    CHECK(sum / (16 * M_PI) == Approx(1).epsilon(0.03));
  }
}
