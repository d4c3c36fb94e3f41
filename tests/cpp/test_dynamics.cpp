#include "diagnostics/capsule_diagnostics.hpp"
#include "dynamics/cpu_flow.hpp"
#include "dynamics/time_schemes.hpp"
#include "dynamics/volume_constraint.hpp"
#include "run/step_failure.hpp"
#include "mesh/surface_geometry.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

// With bending (eb / h^2 = 1.1 at level 2) the automatic step must shrink enough to stay
// stable: at 0.5 Ca h / (1 + eb / h^2) this membrane is unstable (its energy grows).
TEST_CASE("dynamics: a stretched capsule relaxes to a sphere, energy decreasing",
          "[dynamics]") {
  for (double bending : {0.0, 0.1}) {
    INFO("bending modulus " << bending);
    Icosphere s = make_icosphere(2);
    const double ca = 1.0; // Gs = 1
    Membrane membrane(s.topology, s.positions.data(), 1.0 / ca, bending / ca);
    const CpuFlow flow({membrane, 1, 0.0});
    auto x =
        testing::stretched(s.positions, 1.25, 1 / std::sqrt(1.25), 1 / std::sqrt(1.25));
    std::vector<double> v0 = {enclosed_volume(s.topology, s.positions.data())};
    enforce_volume(s.topology, 1, x, v0);
    const double h = mean_edge_length(s.topology, s.positions.data());
    const double dt = automatic_time_step(ca, h, 0.5, bending);
    const int steps = int(std::lround(400 * automatic_time_step(ca, h, 0.5) / dt));
    double w_prev = membrane.energy(x.data()), w0 = w_prev;
    bool monotone = true;
    for (int step = 0; step < steps; ++step) {
      heun_step(flow, x, step * dt, dt);
      enforce_volume(s.topology, 1, x, v0);
      double w = membrane.energy(x.data());
      monotone = monotone && w <= w_prev * (1 + 1e-12) + 1e-12 * w0; // rounding near 0
      w_prev = w;
    }
    check_state(membrane, 1, x, steps * dt);
    CHECK(monotone);
    CHECK(w_prev < 1e-3 * w0);
    Vec3 c = volume_centroid(s.topology, x.data());
    CHECK(taylor_deformation(second_moment(s.topology, x.data(), c)).D < 1e-3);
  }
}

TEST_CASE("dynamics: the volume constraint restores the reference volume", "[dynamics]") {
  Icosphere s = make_icosphere(3);
  auto x = testing::stretched(s.positions, 1.02, 1.03, 0.97);
  std::vector<double> v0 = {enclosed_volume(s.topology, s.positions.data())};
  double before = enforce_volume(s.topology, 1, x, v0)[0];
  CHECK(before == Approx(1.02 * 1.03 * 0.97 - 1).epsilon(1e-12));
  CHECK(std::abs(enclosed_volume(s.topology, x.data()) - v0[0]) / v0[0] < 1e-12);
}

TEST_CASE("dynamics: the velocity with the volume rate removed keeps each capsule's "
          "volume to second order, and leaves a volume-preserving velocity alone",
          "[dynamics]") {
  const Icosphere s = make_icosphere(2);
  const int nn = s.topology.num_nodes;
  // Two capsules: the first deformed and inflating (u = 0.3 x + a swirl), the second a
  // rigid rotation, which keeps the discrete volume exactly.
  std::vector<Vec3> x, u;
  for (const Vec3& p : testing::stretched(s.positions, 1.2, 0.9, 0.95, 0.3)) {
    x.push_back(p);
    u.push_back(0.3 * p + Vec3{-p.y, p.x, 0.2 * p.x * p.z});
  }
  for (const Vec3& p : s.positions) {
    x.push_back(p + Vec3{3, 0, 0});
    u.push_back(Vec3{-p.z, 0, p.x});
  }
  const std::vector<Vec3> rotation(u.begin() + nn, u.end());
  remove_volume_rate(s.topology, 2, x, u);
  for (int c = 0; c < 2; ++c) {
    const Vec3* xc = &x[c * nn];
    const double v = enclosed_volume(s.topology, xc);
    // V(x + e u) - V(x) = O(e^2) once dV/dt = 0: halving e quarters the change.
    double change[2];
    for (int k = 0; k < 2; ++k) {
      const double e = k == 0 ? 1e-3 : 5e-4;
      std::vector<Vec3> moved(xc, xc + nn);
      for (int i = 0; i < nn; ++i)
        moved[i] += e * u[c * nn + i];
      change[k] = std::abs(enclosed_volume(s.topology, moved.data()) - v) / v;
    }
    INFO("capsule " << c << ": relative volume change " << change[0] << ", "
                    << change[1]);
    CHECK(change[0] < 1e-5);
    CHECK(change[0] / change[1] == Approx(4).epsilon(0.05));
  }
  double moved_rotation = 0;
  for (int i = 0; i < nn; ++i)
    moved_rotation = std::max(moved_rotation, norm(u[nn + i] - rotation[i]));
  CHECK(moved_rotation < 1e-12);
}

TEST_CASE("dynamics: blow-up and NaN stop with a clear message", "[dynamics]") {
  Icosphere s = make_icosphere(2);
  const Membrane membrane(s.topology, s.positions.data(), 1.0);
  auto x = s.positions;
  x[5].y = std::nan("");
  CHECK_THROWS_WITH(check_state(membrane, 1, x, 3.0),
                    Catch::Contains("not finite") && Catch::Contains("dt"));
  x = s.positions;
  x[7] = 20.0 * x[7];
  CHECK_THROWS_AS(check_state(membrane, 1, x, 3.0), SimulationError);
  x = s.positions;
  const auto& t = s.topology.triangles[0];
  std::swap(x[t[1]], x[t[2]]); // fold one triangle over
  CHECK_THROWS_WITH(check_state(membrane, 1, x, 3.0), Catch::Contains("inverted"));
  const StateFault f = find_fault(s.topology, 1, x);
  CHECK(f.capsule == 0);
  CHECK(f.triangle == 0);
}

// An inverted triangle among compressed elements is the membrane buckling, not the
// step: the message says so and names what regularises it; among taut ones it keeps
// the time-step advice.
TEST_CASE("dynamics: an inverted triangle in a compressed region blames buckling",
          "[dynamics]") {
  Icosphere s = make_icosphere(2);
  const Membrane membrane(s.topology, s.positions.data(), 1.0);
  const auto& t = s.topology.triangles[0];
  auto fold = [&](std::vector<Vec3> x) {
    std::swap(x[t[1]], x[t[2]]);
    return x;
  };
  // Shrunk to 0.9 of its size, every element is compressed (T2 = (0.81 - 1/0.6561) /
  // 0.9).
  const auto shrunk = fold(testing::stretched(s.positions, 0.9, 0.9, 0.9));
  CHECK_THROWS_WITH(
      check_state(membrane, 1, shrunk, 3.5),
      Catch::Contains("in capsule 0: a surface triangle has inverted; ") &&
          Catch::Contains(" of its 320 elements are in compression (T2 < -0.001 Gs), "
                          "down to T2 = ") &&
          Catch::Contains("Gs next to the inverted one: the membrane buckles") &&
          Catch::Contains("membrane.wrinkling or membrane.bending") &&
          !Catch::Contains("time step is probably"));
  const Membrane wrinkling(s.topology, s.positions.data(), 1.0, 0, true);
  CHECK_THROWS_WITH(check_state(wrinkling, 1, shrunk, 3.5),
                    Catch::Contains("in compression under the paper's energy, which the "
                                    "relaxed membrane does not carry (T2 <") &&
                        Catch::Contains("membrane.wrinkling is on"));
  // Inflated to twice its size, every element stays taut after the fold.
  const auto inflated = fold(testing::stretched(s.positions, 2.0, 2.0, 2.0));
  CHECK_THROWS_WITH(check_state(membrane, 1, inflated, 3.5),
                    Catch::Contains("a surface triangle has inverted. The time step is "
                                    "probably too large") &&
                        !Catch::Contains("compression"));
}

// The guard at the kernels' input (docs/reliability.md, "Numerical guards"): a NaN or
// Inf position, or finite positions whose membrane traction is not finite, stop the
// first evaluation with a message naming the array, the capsule and the node, instead
// of spreading NaN into every velocity.
TEST_CASE("dynamics: a non-finite kernel input stops the first step and is named",
          "[dynamics]") {
  Icosphere s = make_icosphere(1);
  Membrane membrane(s.topology, s.positions.data(), 1.0);
  const CpuFlow flow({membrane, 1, 1.0});
  std::vector<Vec3> u;
  auto x = s.positions;
  x[7].y = NAN;
  CHECK_THROWS_WITH(flow.velocity(x, 0.0, u),
                    Catch::Contains("the position at node 7 is not finite"));
  x = s.positions;
  for (Vec3& p : x) // finite, but the stretch energy overflows
    p = 1e160 * p;
  CHECK_THROWS_WITH(heun_step(flow, x, 0.0, 1e-3), Catch::Contains("membrane traction") &&
                                                      Catch::Contains("in capsule 0"));
  CHECK_THROWS_AS(heun_step(flow, x, 0.0, 1e-3), SimulationError);
}
