// The relaxed (tension-field) neo-Hookean element, membrane/tension_field.hpp, and its
// Hessian: its energy against eq. 2.11, its tensions, its exact gradient and Hessian in
// the taut, wrinkled and slack regions, and its continuity across their borders.
#include "membrane/membrane_forces.hpp"
#include "membrane/neo_hookean_hessian.hpp"
#include "mesh/surface_geometry.hpp"
#include "test_helpers.hpp"

#include <array>
#include <catch2/catch.hpp>
#include <random>

using namespace capsim;

namespace {

// A reference element in the plane z = 0, neither equilateral nor aligned with the axes.
const Vec3 kReference[3] = {{0, 0, 0}, {1, 0.1, 0}, {0.2, 0.9, 0}};
constexpr double kGs = 0.7;

const ElementReference& reference() {
  static const ElementReference ref =
      make_element_reference(kReference[0], kReference[1], kReference[2]);
  return ref;
}

// The element under the in-plane deformation with principal stretches l1, l2 (major axis
// at angle theta from x), then turned out of the plane: x = R (F X) + shift.
struct Deformed {
  Vec3 x[3];
};

Deformed deformed(double l1, double l2, double theta = 0.3) {
  const double c = std::cos(theta), s = std::sin(theta);
  const double ca = std::cos(0.7), sa = std::sin(0.7), cb = std::cos(-0.4),
               sb = std::sin(-0.4);
  Deformed d;
  for (int k = 0; k < 3; ++k) {
    const Vec3 p = kReference[k];
    // F = Q diag(l1, l2) Q^T with Q the rotation by theta.
    const double u = c * p.x + s * p.y, v = -s * p.x + c * p.y;
    const double fx = c * l1 * u - s * l2 * v, fy = s * l1 * u + c * l2 * v;
    // Rotate about x by 0.7, then about z by -0.4, and shift.
    const Vec3 q{fx, ca * fy, sa * fy};
    d.x[k] = Vec3{cb * q.x - sb * q.y, sb * q.x + cb * q.y, q.z} + Vec3{0.3, -0.2, 0.1};
  }
  return d;
}

double relaxed_energy(const Deformed& d, Vec3 grad[3]) {
  for (int k = 0; k < 3; ++k)
    grad[k] = Vec3{};
  return tension_field_element(reference(), kGs, d.x[0], d.x[1], d.x[2], grad);
}

double neo_hookean_energy(const Deformed& d) {
  Vec3 grad[3];
  return neo_hookean_element(reference(), kGs, d.x[0], d.x[1], d.x[2], grad);
}

// The largest difference between the element gradient and central differences of its
// energy, and the largest finite difference.
std::pair<double, double> element_gradient_error(const Deformed& d) {
  Vec3 grad[3];
  relaxed_energy(d, grad);
  const double h = 1e-6;
  double worst = 0, scale = 0;
  for (int j = 0; j < 9; ++j) {
    Deformed p = d, m = d;
    (&p.x[j / 3].x)[j % 3] += h;
    (&m.x[j / 3].x)[j % 3] -= h;
    Vec3 unused[3];
    const double fd = (relaxed_energy(p, unused) - relaxed_energy(m, unused)) / (2 * h);
    worst = std::max(worst, std::abs(fd - (&grad[j / 3].x)[j % 3]));
    scale = std::max(scale, std::abs(fd));
  }
  return {worst, scale};
}

// The largest difference between the element Hessian and central differences of the
// gradient, and the Hessian's largest entry.
std::pair<double, double> element_hessian_error(const Deformed& d) {
  const Matrix9 h =
      tension_field_element_hessian(reference(), kGs, d.x[0], d.x[1], d.x[2]);
  const double step = 1e-6;
  double worst = 0;
  for (int j = 0; j < 9; ++j) {
    Deformed p = d, m = d;
    (&p.x[j / 3].x)[j % 3] += step;
    (&m.x[j / 3].x)[j % 3] -= step;
    Vec3 gp[3], gm[3];
    relaxed_energy(p, gp);
    relaxed_energy(m, gm);
    for (int i = 0; i < 9; ++i) {
      const double fd = ((&gp[i / 3].x)[i % 3] - (&gm[i / 3].x)[i % 3]) / (2 * step);
      worst = std::max(worst, std::abs(fd - h(i, j)));
    }
  }
  return {worst, h.cwiseAbs().maxCoeff()};
}

double max_difference(const Vec3 a[3], const Vec3 b[3]) {
  double d = 0;
  for (int k = 0; k < 3; ++k)
    d = std::max(d, norm(a[k] - b[k]));
  return d;
}

TensionState state_of(double l1, double l2) {
  const Deformed d = deformed(l1, l2);
  const Vec3 e1 = d.x[1] - d.x[0], e2 = d.x[2] - d.x[0];
  return tension_state(
      squared_stretches(reference(), dot(e1, e1), dot(e1, e2), dot(e2, e2)));
}

// One state of each region, and the isotropic states on either side of l = 1.
struct Case {
  const char* name;
  double l1, l2;
  TensionState state;
};
const Case kCases[] = {
    {"taut", 1.3, 1.0, TensionState::taut},
    {"taut, isotropic", 1.1, 1.1, TensionState::taut},
    {"taut, compressed minor stretch", 1.6, 0.85, TensionState::taut},
    {"wrinkled", 1.3, 0.8, TensionState::wrinkled},
    {"wrinkled, strongly", 2.0, 0.3, TensionState::wrinkled},
    {"wrinkled, next to slack", 1.001, 0.99, TensionState::wrinkled},
    {"slack", 0.95, 0.8, TensionState::slack},
    {"slack, isotropic", 0.9, 0.9, TensionState::slack},
};

// A derivative's finite-difference error (worst, scale) in a state: to 1e-7 of its scale,
// and exactly zero, as the derivative itself, where slack.
void check_exact(std::pair<double, double> error, TensionState state) {
  const auto [worst, scale] = error;
  if (state == TensionState::slack) {
    CHECK(worst == 0);
    CHECK(scale == 0);
  } else {
    CHECK(worst < 1e-7 * scale);
  }
}

} // namespace

TEST_CASE("tension field: the regions of the stretches", "[tension_field]") {
  for (const Case& c : kCases) {
    INFO(c.name);
    CHECK(state_of(c.l1, c.l2) == c.state);
  }
  // The border T2 = 0 is l2 = l1^(-1/2).
  CHECK(state_of(1.44, 1 / 1.2 * 1.0001) == TensionState::taut);
  CHECK(state_of(1.44, 1 / 1.2 * 0.9999) == TensionState::wrinkled);
  // The reference state lies where the three regions meet: whichever one round-off puts
  // it in, it is stress-free.
  Vec3 grad[3];
  CHECK(std::abs(relaxed_energy(deformed(1.0, 1.0), grad)) < 1e-15);
  CHECK(max_difference(grad, std::array<Vec3, 3>{}.data()) < 1e-13);
  const Deformed d = deformed(1.0, 1.0);
  const ElementTensions t = tension_field_tensions(reference(), d.x[0], d.x[1], d.x[2]);
  CHECK(std::abs(t.t1) < 1e-13);
  CHECK(std::abs(t.t2) < 1e-13);
}

TEST_CASE("tension field: the relaxed energy is eq. 2.11 where taut and below it "
          "otherwise",
          "[tension_field]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> stretch(0.3, 2.5), angle(0, 3.14159);
  int counted[3] = {0, 0, 0};
  for (int n = 0; n < 2000; ++n) {
    double l1 = stretch(rng), l2 = stretch(rng);
    if (l2 > l1)
      std::swap(l1, l2);
    const Deformed d = deformed(l1, l2, angle(rng));
    Vec3 grad[3];
    const double relaxed = relaxed_energy(d, grad), neo = neo_hookean_energy(d);
    const double t2 = neo_hookean_tensions(reference(), d.x[0], d.x[1], d.x[2]).t2;
    INFO("l1 " << l1 << ", l2 " << l2 << ": relaxed " << relaxed << ", eq. 2.11 " << neo);
    CHECK(relaxed >= 0);
    if (t2 >= 0) {
      CHECK(relaxed == neo);
      ++counted[0];
    } else {
      CHECK(relaxed < neo);
      ++counted[l1 > 1 ? 1 : 2];
    }
    // In closed form: c (L1 + 2 / l1 - 3) where wrinkled, 0 where slack.
    const double c = 0.5 * kGs * reference().area0;
    if (t2 < 0 && l1 > 1)
      CHECK(relaxed == Approx(c * (l1 * l1 + 2 / l1 - 3)).epsilon(1e-11).margin(1e-14));
    if (l1 <= 1)
      CHECK(relaxed == 0);
  }
  CHECK(counted[0] > 100);
  CHECK(counted[1] > 100);
  CHECK(counted[2] > 100);
}

TEST_CASE("tension field: the relaxed tensions are never negative", "[tension_field]") {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> stretch(0.3, 2.5), angle(0, 3.14159);
  for (int n = 0; n < 2000; ++n) {
    double l1 = stretch(rng), l2 = stretch(rng);
    if (l2 > l1)
      std::swap(l1, l2);
    const Deformed d = deformed(l1, l2, angle(rng));
    const ElementTensions t = tension_field_tensions(reference(), d.x[0], d.x[1], d.x[2]);
    const ElementTensions neo = neo_hookean_tensions(reference(), d.x[0], d.x[1], d.x[2]);
    INFO("l1 " << l1 << ", l2 " << l2);
    CHECK(t.t2 >= 0);
    CHECK(t.t1 >= t.t2);
    CHECK(t.dilatation == Approx(l1 * l2).epsilon(1e-12));
    if (neo.t2 >= 0) { // taut: eq. 2.10
      CHECK(t.t1 == neo.t1);
      CHECK(t.t2 == neo.t2);
    } else if (l1 > 1) { // wrinkled: uniaxial, T1 = Gs (l1 - l1^-2) / l2
      CHECK(t.t2 == 0);
      CHECK(t.t1 == Approx((l1 - 1 / (l1 * l1)) / l2).epsilon(1e-11));
    } else { // slack
      CHECK(t.t1 == 0);
      CHECK(t.t2 == 0);
    }
  }
}

TEST_CASE("tension field: the gradient is exact in taut, wrinkled and slack states "
          "(finite differences)",
          "[tension_field]") {
  for (const Case& c : kCases) {
    INFO(c.name);
    check_exact(element_gradient_error(deformed(c.l1, c.l2)), c.state);
  }
  // A whole capsule squashed along x and shrunk along z, perturbed: slack, wrinkled and
  // taut elements at once.
  const Icosphere s = make_icosphere(2);
  const Membrane membrane(s.topology, s.positions.data(), kGs, 0, true);
  const auto x =
      testing::perturbed(testing::stretched(s.positions, 0.85, 1.25, 0.95, 0.4), 0.02, 5);
  int states[3] = {0, 0, 0};
  for (const auto& t : s.topology.triangles) {
    const Vec3 e1 = x[t[1]] - x[t[0]], e2 = x[t[2]] - x[t[0]];
    const ElementReference ref =
        make_element_reference(s.positions[t[0]], s.positions[t[1]], s.positions[t[2]]);
    ++states[int(
        tension_state(squared_stretches(ref, dot(e1, e1), dot(e1, e2), dot(e2, e2))))];
  }
  INFO("taut " << states[0] << ", wrinkled " << states[1] << ", slack " << states[2]);
  CHECK(states[0] > 0);
  CHECK(states[1] > 0);
  CHECK(states[2] > 0);
  std::vector<Vec3> grad;
  membrane.energy_gradient(x.data(), grad);
  const auto [worst, scale] = testing::gradient_check(
      [&](const Vec3* p) { return membrane.energy(p); }, x, grad, 3);
  CHECK(worst / scale < 1e-7);
}

TEST_CASE("tension field: energy and force are continuous across the taut/wrinkled and "
          "wrinkled/slack borders",
          "[tension_field]") {
  // Across l2 = l1^(-1/2) at l1 = 1.4, and across l1 = 1 at l2 = 0.9: the jump of the
  // energy and of the force over a gap 2 delta shrinks with delta (value and first
  // derivative agree on the border), while the force itself does not vanish.
  const double l1 = 1.4, border = 1 / std::sqrt(l1);
  for (double delta : {1e-4, 1e-6, 1e-8}) {
    INFO("delta " << delta);
    Vec3 g_taut[3], g_wrinkled[3];
    const double w_taut = relaxed_energy(deformed(l1, border * (1 + delta)), g_taut);
    const double w_wrinkled =
        relaxed_energy(deformed(l1, border * (1 - delta)), g_wrinkled);
    REQUIRE(state_of(l1, border * (1 + delta)) == TensionState::taut);
    REQUIRE(state_of(l1, border * (1 - delta)) == TensionState::wrinkled);
    const double force = std::max(norm(g_taut[1]), norm(g_taut[2]));
    CHECK(force > 0.1);
    // The energy changes by O(delta) (the force along l2 vanishes on the border), the
    // force by O(delta) too.
    CHECK(std::abs(w_taut - w_wrinkled) < 10 * delta * w_taut);
    CHECK(max_difference(g_taut, g_wrinkled) < 10 * delta * force);
    // On the wrinkled side eq. 2.11 is above the relaxed energy by O(delta^2) only.
    CHECK(neo_hookean_energy(deformed(l1, border * (1 - delta))) - w_wrinkled <
          10 * delta * delta * w_taut + 1e-15);

    Vec3 g_slack[3], g_wrinkled_near[3];
    const double w_slack = relaxed_energy(deformed(1 - delta, 0.9), g_slack);
    const double w_near = relaxed_energy(deformed(1 + delta, 0.9), g_wrinkled_near);
    REQUIRE(state_of(1 + delta, 0.9) == TensionState::wrinkled);
    CHECK(w_slack == 0);
    CHECK(w_near < 10 * delta * delta);
    CHECK(max_difference(g_slack, g_wrinkled_near) < 10 * delta);
  }
}

TEST_CASE("tension field: the Hessian is the derivative of the forces in every region",
          "[tension_field]") {
  for (const Case& c : kCases) {
    INFO(c.name);
    check_exact(element_hessian_error(deformed(c.l1, c.l2)), c.state);
  }
  // Where taut, the relaxed Hessian is eq. 2.11's, and so is the switch of the membrane.
  const Deformed d = deformed(1.3, 1.0);
  const Matrix9 relaxed =
      tension_field_element_hessian(reference(), kGs, d.x[0], d.x[1], d.x[2]);
  const Matrix9 neo =
      neo_hookean_element_hessian(reference(), kGs, d.x[0], d.x[1], d.x[2]);
  CHECK((relaxed - neo).cwiseAbs().maxCoeff() == 0);
  const Deformed w = deformed(1.3, 0.8);
  CHECK((membrane_element_hessian(reference(), kGs, true, w.x[0], w.x[1], w.x[2]) -
         tension_field_element_hessian(reference(), kGs, w.x[0], w.x[1], w.x[2]))
            .cwiseAbs()
            .maxCoeff() == 0);
}

TEST_CASE("tension field: the membrane switch picks one function for the CPU and the "
          "device",
          "[tension_field]") {
  // The CUDA kernel calls membrane_element with the membrane's flag (cuda/
  // membrane_kernels.cu); here it must be the relaxed element with the flag and eq. 2.11
  // without it, and the CPU assembly must sum exactly those.
  const Deformed d = deformed(1.3, 0.8);
  Vec3 a[3], b[3], c[3], e[3];
  const double relaxed =
      membrane_element(reference(), kGs, true, d.x[0], d.x[1], d.x[2], a);
  CHECK(relaxed == tension_field_element(reference(), kGs, d.x[0], d.x[1], d.x[2], b));
  CHECK(max_difference(a, b) == 0);
  const double neo = membrane_element(reference(), kGs, false, d.x[0], d.x[1], d.x[2], c);
  CHECK(neo == neo_hookean_element(reference(), kGs, d.x[0], d.x[1], d.x[2], e));
  CHECK(max_difference(c, e) == 0);
  CHECK(relaxed < neo);

  const Icosphere s = make_icosphere(1);
  const Membrane membrane(s.topology, s.positions.data(), kGs, 0, true);
  const auto x = testing::stretched(s.positions, 0.8, 1.2, 1.0);
  std::vector<Vec3> grad, sum(x.size());
  double total = 0;
  for (size_t k = 0; k < s.topology.triangles.size(); ++k) {
    const auto& t = s.topology.triangles[k];
    Vec3 g[3];
    total += membrane_element(membrane.references()[k], kGs, true, x[t[0]], x[t[1]],
                              x[t[2]], g);
    for (int i = 0; i < 3; ++i)
      sum[t[i]] += g[i];
  }
  CHECK(membrane.energy_gradient(x.data(), grad) == total);
  for (size_t i = 0; i < x.size(); ++i)
    CHECK(norm(grad[i] - sum[i]) == 0);
}
