#include "dynamics/cpu_flow.hpp"
#include "dynamics/time_schemes.hpp"
#include "dynamics/volume_constraint.hpp"
#include "mesh/surface_geometry.hpp"
#include "stepping_helpers.hpp"
#include "test_helpers.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace capsim;

namespace {

// R(z): one RKC step of dt = 1 on y' = z y from y = 1 (the scheme's stability function).
double rkc_amplification(const RkcCoefficients& k, double z) {
  std::vector<Vec3> y = {{1, 0, 0}}, u0;
  rkc_step(
      k,
      [z](const std::vector<Vec3>& x, double, std::vector<Vec3>& u) { u = {z * x[0]}; },
      y, 0.0, 1.0, u0);
  return y[0].x;
}

} // namespace

TEST_CASE("time schemes: rkc is second order, its stages end at t + dt, and it is stable "
          "on [-beta(s), 0]",
          "[time_schemes]") {
  for (int s : {2, 3, 4, 6, 10}) {
    INFO("stages " << s);
    const RkcCoefficients k = rkc_coefficients(s);
    // beta(s) ~ (2/3)(s^2 - 1)(1 - 2 eps / 15), eps = 2/13 (Sommeijer et al. 1998, 2.7),
    // the better the more stages.
    CHECK(k.beta == Approx(2.0 / 3.0 * (s * s - 1) * (1 - 4.0 / 195)).epsilon(0.03));
    CHECK(k.c[s] == Approx(1.0).epsilon(1e-12));
    // |R(z)| <= 1 on the whole interval (the damping keeps |R| below 1 a little beyond
    // it), and an explicit step's interval is finite: at twice beta the step grows.
    double largest = 0;
    for (int i = 0; i <= 2000; ++i)
      largest = std::max(largest, std::abs(rkc_amplification(k, -k.beta * i / 2000.0)));
    CHECK(largest <= 1 + 1e-9);
    CHECK(std::abs(rkc_amplification(k, -2 * k.beta)) > 1);
    // Local error R(-h) - exp(-h) = O(h^3): second order.
    const double e1 = std::abs(rkc_amplification(k, -0.02) - std::exp(-0.02));
    const double e2 = std::abs(rkc_amplification(k, -0.01) - std::exp(-0.01));
    CHECK(testing::observed_order(e1, e2) == Approx(3).margin(0.1));
  }
  // The stage times: y' = t is integrated exactly by a second-order step.
  const RkcCoefficients k = rkc_coefficients(4);
  std::vector<Vec3> y = {{0, 0, 0}}, u0;
  rkc_step(
      k,
      [](const std::vector<Vec3>&, double t, std::vector<Vec3>& u) {
        u = {{t, 0, 0}};
      },
      y, 0.5, 0.3, u0);
  CHECK(y[0].x == Approx(0.5 * (0.8 * 0.8 - 0.5 * 0.5)).epsilon(1e-12));
}

TEST_CASE("time schemes: a capsule's rkc step converges at second order, to Heun's "
          "solution",
          "[time_schemes]") {
  // One capsule in shear at mesh level 1 from a stretched shape to gammadot t = 0.4, as
  // the IMEX scheme's test: the positions against Heun's at a 64 times finer step.
  const Icosphere s = make_icosphere(1);
  const Membrane membrane(s.topology, s.positions.data(), 1.0 / 0.2);
  const CpuFlow flow({membrane, 1, 1.0});
  const std::vector<double> v0 = {enclosed_volume(s.topology, s.positions.data())};
  auto solve = [&](TimeScheme scheme, int steps) {
    auto stepper = make_stepper(scheme, flow, ErrorNorm::max, 4);
    auto x = testing::stretched(s.positions, 1.2, 1 / std::sqrt(1.2), 1 / std::sqrt(1.2));
    testing::advance(*stepper, s.topology, 1, x, v0, 0.4 / steps, steps);
    return x;
  };
  const auto reference = solve(TimeScheme::heun, 2048);
  std::vector<double> error;
  for (int steps : {8, 16, 32}) {
    error.push_back(testing::largest_distance(solve(TimeScheme::rkc, steps), reference));
  }
  INFO("errors " << error[0] << " " << error[1] << " " << error[2]);
  CHECK(testing::observed_order(error[0], error[1]) > 1.8);
  CHECK(testing::observed_order(error[1], error[2]) > 1.8);
}

TEST_CASE("time schemes: rkc relaxes a stretched capsule at a step where Heun's grows",
          "[time_schemes]") {
  // At 3 times the automatic step of dt_safety 1 (Heun's limit is 1.4-1.6 of it), within
  // beta(4) / 2 = 4.9 times that limit.
  const Icosphere s = make_icosphere(2);
  const double ca = 0.2;
  const Membrane membrane(s.topology, s.positions.data(), 1.0 / ca);
  const CpuFlow flow({membrane, 1, 0.0}); // quiescent
  const double h = mean_edge_length(s.topology, s.positions.data());
  const double dt = automatic_time_step(ca, h, 3.0);
  std::vector<double> v0 = {enclosed_volume(s.topology, s.positions.data())};
  for (TimeScheme scheme : {TimeScheme::rkc, TimeScheme::heun}) {
    auto stepper = make_stepper(scheme, flow, ErrorNorm::max, 4);
    auto x = testing::stretched(s.positions, 1.2, 1 / std::sqrt(1.2), 1 / std::sqrt(1.2));
    enforce_volume(s.topology, 1, x, v0);
    const double w0 = membrane.energy(x.data());
    const bool finite = testing::stays_bounded(*stepper, s.topology, 1, x, v0, dt, 100);
    INFO(to_string(scheme) << " at 3 Ca h");
    if (scheme == TimeScheme::rkc) {
      REQUIRE(finite);
      CHECK(membrane.energy(x.data()) < 1e-2 * w0);
    } else {
      CHECK_FALSE(finite);
    }
  }
}
