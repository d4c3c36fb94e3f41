// The drop mode (membrane.law: drop): an isotropic surface tension instead of the
// membrane, whose exact small-deformation results test the viscosity ratio lambda (issue
// 49): Taylor's (1932) deformation D / Ca = (19 lambda + 16) / (16 lambda + 16) and
// intrinsic viscosity [mu] = (5 lambda + 2) / (2 lambda + 2), and Chaffey & Brenner's
// (1967) angle (pi/4 - theta) / Ca = (19 lambda + 16)(2 lambda + 3) / (80 (lambda + 1)),
// Ca = mu gammadot a / sigma. A drop's steady state has no time-stepping error (a
// Runge-Kutta scheme's fixed points are the flow's), so what is left is the mesh and the
// O(Ca^2) terms of the expansion, each measured here by its observed order.
#include "config/run_options.hpp"
#include "diagnostics/averages.hpp"
#include "dynamics/normal_motion.hpp"
#include "io/timeseries_file.hpp"
#include "membrane/membrane_forces.hpp"
#include "mesh/icosphere.hpp"
#include "mesh/surface_geometry.hpp"
#include "run/flow_factory.hpp"
#include "run/simulation.hpp"
#include "test_helpers.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace capsim;

namespace {

double taylor_deformation(double lambda) { // D / Ca
  return (19 * lambda + 16) / (16 * lambda + 16);
}
double chaffey_brenner_angle(double lambda) { // (pi/4 - theta) / Ca
  return (19 * lambda + 16) * (2 * lambda + 3) / (80 * (lambda + 1));
}
double taylor_viscosity(double lambda) { // [mu]
  return 2.5 * (lambda + 0.4) / (lambda + 1);
}

// What the small-deformation theory predicts, scaled by Ca where it grows with Ca.
struct DropValues {
  double d_over_ca = 0, angle_over_ca = 0, mu = 0;
};

// Taylor's relaxation time of a drop, Ca (2 lambda + 3)(19 lambda + 16) / (40 (lambda +
// 1)) (Rallison 1984, Annu. Rev. Fluid Mech. 16, 45).
double relaxation_time(double ca, double lambda) {
  return ca * (2 * lambda + 3) * (19 * lambda + 16) / (40 * (lambda + 1));
}

// The samples of a drop's run at Ca, lambda and mesh level to gammadot t = t_end, with
// `more` settings (in a folder of its own, removed afterwards).
std::vector<Sample> drop_run(double ca, double lambda, int level, double t_end,
                             std::vector<std::string> more = {}) {
  const fs::path dir =
      fs::temp_directory_path() /
      ("capsim_drop_" + std::to_string(getpid()) + "_" + std::to_string(lambda) + "_" +
       std::to_string(ca) + "_" + std::to_string(level));
  fs::remove_all(dir);
  std::vector<std::string> settings = {"membrane.law=drop",
                                       "ca=" + std::to_string(ca),
                                       "lambda=" + std::to_string(lambda),
                                       "mesh_level=" + std::to_string(level),
                                       "t_end=" + std::to_string(t_end),
                                       "output.snapshot_interval=0",
                                       "output.checkpoint_interval=100"};
  settings.insert(settings.end(), more.begin(), more.end());
  RunRequest r;
  r.options = parse_run_options("", settings);
  r.outdir = dir.string();
  r.quiet = true;
  run_simulation(r);
  std::vector<Sample> samples = read_timeseries((dir / "timeseries.h5").string());
  fs::remove_all(dir);
  return samples;
}

// A drop from the sphere, averaged over one strain unit from 12 relaxation times (at
// least gammadot t = 1): steady to e^-12.
DropValues steady_drop(double ca, double lambda, int level) {
  const double t0 = std::max(1.0, 12 * relaxation_time(ca, lambda)), t1 = t0 + 1;
  const RunAverages a = time_average(
      drop_run(ca, lambda, level, t1, {"t_avg_start=" + std::to_string(t0)}), t0, t1);
  return {a.D_mean / ca, (45 - a.theta_D_mean) * kPi / 180 / ca,
          rheology_from_stresslet(a.stresslet_mean, 0.0, ca).mu_sp};
}

// The values at Ca, 2 Ca and 4 Ca on one mesh, their observed orders in Ca (the
// differences cancel the mesh's error, which does not depend on Ca) and their limits
// Ca -> 0 by Richardson extrapolation with the order 2 of the expansion.
struct CaSeries {
  DropValues at[3];
  DropValues order, limit;
};

CaSeries ca_series(double ca, double lambda, int level) {
  CaSeries s;
  for (int k = 0; k < 3; ++k)
    s.at[k] = steady_drop(ca * (1 << k), lambda, level);
  auto order = [&](double DropValues::*v) {
    return std::log2((s.at[2].*v - s.at[1].*v) / (s.at[1].*v - s.at[0].*v));
  };
  auto limit = [&](double DropValues::*v) { return (4 * s.at[0].*v - s.at[1].*v) / 3; };
  s.order = {order(&DropValues::d_over_ca), order(&DropValues::angle_over_ca),
             order(&DropValues::mu)};
  s.limit = {limit(&DropValues::d_over_ca), limit(&DropValues::angle_over_ca),
             limit(&DropValues::mu)};
  return s;
}

} // namespace

TEST_CASE("drop: the surface tension's force is the area's gradient, and a sphere's load "
          "is Laplace's 2 sigma n",
          "[drop]") {
  const Icosphere mesh = make_icosphere(3);
  const double sigma = 2.5;
  const Membrane drop(mesh.topology, mesh.positions.data(), sigma, 0, false,
                      MembraneLaw::drop);
  const std::vector<Vec3> x =
      testing::perturbed(testing::stretched(mesh.positions, 1.3, 0.9, 0.8), 0.01, 7);
  std::vector<Vec3> grad;
  const double w = drop.energy_gradient(x.data(), grad);
  CHECK(w == Approx(sigma * surface_area(mesh.topology, x.data())).epsilon(1e-12));
  const auto [worst, scale] =
      testing::gradient_check([&](const Vec3* p) { return drop.energy(p); }, x, grad, 7);
  CHECK(worst < 1e-7 * scale);

  // Laplace's jump 2 sigma / R n on the sphere: exactly on average, as W is homogeneous
  // of degree 2 in x (sum_i x_i . dW/dx_i = 2 W); node by node within the scatter of
  // the lumped curvature on the icosphere's unequal triangles (RMS 3.8 %, 2.0 %, 1.0 % at
  // levels 2-4: order 1; the 12 nodes of five neighbours differ most, 14 % at every
  // level, which the drop's own equilibrium shape absorbs: the static drop below).
  double previous_rms = 1;
  for (int level = 2; level <= 4; ++level) {
    const Icosphere sphere = make_icosphere(level);
    const Membrane d(sphere.topology, sphere.positions.data(), sigma, 0, false,
                     MembraneLaw::drop);
    std::vector<Vec3> g, q;
    const double energy = d.energy_gradient(sphere.positions.data(), g);
    d.nodal_load(sphere.positions.data(), g, LoadMapping::lumped, q);
    double virial = 0, rms = 0;
    for (size_t i = 0; i < q.size(); ++i) {
      virial += dot(sphere.positions[i], g[i]);
      const double normal = dot(q[i], sphere.positions[i]) / norm(sphere.positions[i]);
      rms += std::pow(normal / (2 * sigma) - 1, 2);
    }
    rms = std::sqrt(rms / q.size());
    INFO("level " << level << ": RMS deviation of q . n from 2 sigma " << rms);
    CHECK(virial == Approx(2 * energy).epsilon(1e-12));
    CHECK(rms < 0.6 * previous_rms);
    previous_rms = rms;
  }
}

TEST_CASE("drop: membrane.law drop refuses bending, wrinkling and imex by name; the cuda "
          "backend refuses drops",
          "[drop]") {
  CHECK(parse_run_options("", {"membrane.law=drop"}).law == MembraneLaw::drop);
  CHECK_THROWS_WITH(parse_run_options("", {"membrane.law=foam"}),
                    Catch::Contains("membrane.law") && Catch::Contains("neo_hookean"));
  CHECK_THROWS_WITH(
      parse_run_options("", {"membrane.law=drop", "membrane.bending=0.01"}),
      Catch::StartsWith("membrane.bending: must be 0 with membrane.law: drop"));
  CHECK_THROWS_WITH(
      parse_run_options("", {"membrane.law=drop", "membrane.wrinkling=true"}),
      Catch::StartsWith("membrane.wrinkling: must be false"));
  CHECK_THROWS_WITH(parse_run_options("", {"membrane.law=drop", "time.scheme=imex"}),
                    Catch::StartsWith("time.scheme: must be heun or rkc"));
  const Icosphere mesh = make_icosphere(1);
  const Membrane drop(mesh.topology, mesh.positions.data(), 1, 0, false,
                      MembraneLaw::drop);
  CHECK(unsupported_by(FlowSetup(drop), capabilities_of(Backend::cuda), Backend::cuda)
            .rfind("membrane.law: must be neo_hookean with backend: cuda", 0) == 0);
  CHECK(unsupported_by(FlowSetup(drop), capabilities_of(Backend::cpu), Backend::cpu)
            .empty());
}

TEST_CASE(
    "drop: its nodes keep a translation and the normal motion, not the surface flow",
    "[drop]") {
  const Icosphere mesh = make_icosphere(2);
  const int n = mesh.topology.num_nodes;
  // On the sphere a rotation is tangential: the nodes keep only the translation, up to
  // the tilt of the area-weighted node normals against the radius (measured 0.022 |Omega|
  // at level 2).
  const Vec3 translation{0.3, -0.2, 0.1}, omega{0.2, -0.5, 1.0};
  std::vector<Vec3> u(n);
  for (int i = 0; i < n; ++i)
    u[i] = translation + cross(omega, mesh.positions[i]);
  keep_normal_motion(mesh.topology, 1, mesh.positions, u);
  double worst = 0;
  for (const Vec3& v : u)
    worst = std::max(worst, norm(v - translation));
  CHECK(worst < 0.03 * norm(omega));
  // On an ellipsoid the volume rate sum_i dV/dx_i . u_i stays as it was (an expansion
  // plus a shear flow here, capsule after capsule).
  const std::vector<Vec3> x = testing::stretched(mesh.positions, 1.2, 0.9, 0.95, 0.4);
  std::vector<Vec3> both = x, w(2 * n);
  for (int i = 0; i < n; ++i) {
    both.push_back(x[i] + Vec3{5, 0, 0});
    w[i] = 0.1 * x[i] + Vec3{x[i].y, 0, 0};
    w[n + i] = Vec3{x[i].y, 0, 0};
  }
  std::vector<Vec3> v = w;
  keep_normal_motion(mesh.topology, 2, both, v);
  const std::vector<Vec3> nu = node_area_vectors(mesh.topology, x.data());
  for (int c = 0; c < 2; ++c) {
    double rate_w = 0, rate_v = 0;
    for (int i = 0; i < n; ++i) {
      rate_w += dot(nu[i], w[c * n + i]);
      rate_v += dot(nu[i], v[c * n + i]);
    }
    CHECK(rate_v == Approx(rate_w).margin(1e-12));
  }
}

// lambda != 1 on the level-2 mesh, from Ca to 4 Ca (Ca lambda <= 0.25, where the
// expansion's O(Ca^2) terms stay small). Measured limits Ca -> 0 against the theory,
// level 2 (level 3 at the smallest Ca, docs/dilute_limit.md): lambda 0.1 D/Ca +2.2 %
// (+1.0 %), angle -3.6 % (-0.4 %), [mu] +7.0 % (+2.6 %); lambda 5 -0.0 %, -5.3 %, -1.2 %;
// lambda 10 -0.1 %, -5.1 %, -1.2 %; orders in Ca 1.9-2.1. Tolerances: 1.35 times the
// largest level-2 error of each quantity over lambda (D 3 %, angle 7.5 %, [mu] 2 %, at
// lambda 0.1 9.5 %, the one that needs level 3 to come within 3 %), orders within 0.3
// of 2.
static void check_taylor(double lambda, double ca, double mu_tolerance) {
  const CaSeries s = ca_series(ca, lambda, 2);
  INFO("lambda " << lambda << ": limits D/Ca " << s.limit.d_over_ca << " (Taylor "
                 << taylor_deformation(lambda) << "), angle/Ca " << s.limit.angle_over_ca
                 << " (Chaffey-Brenner " << chaffey_brenner_angle(lambda) << "), [mu] "
                 << s.limit.mu << " (Taylor " << taylor_viscosity(lambda)
                 << "); orders in Ca " << s.order.d_over_ca << ", " << s.order.mu);
  CHECK(s.order.d_over_ca == Approx(2).margin(0.3));
  CHECK(s.order.mu == Approx(2).margin(0.3));
  CHECK(s.limit.d_over_ca == Approx(taylor_deformation(lambda)).epsilon(0.03));
  CHECK(s.limit.angle_over_ca == Approx(chaffey_brenner_angle(lambda)).epsilon(0.075));
  CHECK(s.limit.mu == Approx(taylor_viscosity(lambda)).epsilon(mu_tolerance));
}

TEST_CASE("drop: Taylor and Chaffey-Brenner at lambda 0.1", "[drop][physics]") {
  check_taylor(0.1, 0.025, 0.095);
}

TEST_CASE("drop: Taylor and Chaffey-Brenner at lambda 5", "[drop][physics]") {
  check_taylor(5, 0.0125, 0.02);
}

TEST_CASE("drop: Taylor and Chaffey-Brenner at lambda 10", "[drop][physics]") {
  check_taylor(10, 0.00625, 0.02);
}

// A drop stretched to D = 0.071 in quiescent fluid relaxes with Taylor's time
// (relaxation_time above). The time fitted to log D over [0.2, 1] of it is 21 % (level 2)
// and 9 % (level 3) longer at lambda 1: order 1.1 in h, the order of the lumped
// curvature's scatter (first test); its ratio to lambda 1's on the same mesh, where that
// error cancels, is Taylor's ratio to 0.7 % (lambda 0.1) and 2.3 % (lambda 10), where
// Taylor's time varies 4.9-fold. Tolerances: the ratios within 4 %, the mesh order at
// least 0.8 (measured 1.2).
static double fitted_relaxation(double lambda, int level) {
  const double ca = 0.1, tau = relaxation_time(ca, lambda);
  const std::vector<Sample> series = drop_run(
      ca, lambda, level, tau, {"flow=quiescent", "initial.stretch=1.1", "t_avg_start=0"});
  // Least-squares slope of log D against t over [0.2 tau, tau].
  double n = 0, st = 0, sl = 0, stt = 0, stl = 0;
  for (const Sample& row : series) {
    const double t = row.time;
    if (t < 0.2 * tau)
      continue;
    const double l = std::log(row.capsules[0].taylor_D);
    n += 1, st += t, sl += l, stt += t * t, stl += t * l;
  }
  const double slope = (n * stl - st * sl) / (n * stt - st * st);
  return -1 / slope / tau; // the fitted time over Taylor's
}

TEST_CASE(
    "drop: a stretched drop relaxes with Taylor's time, its lambda dependence exact",
    "[drop][physics]") {
  const double one = fitted_relaxation(1, 2);
  const double fine = fitted_relaxation(1, 3);
  const double low = fitted_relaxation(0.1, 2);
  const double high = fitted_relaxation(10, 2);
  INFO("fitted over Taylor's time: lambda 1 " << one << " (level 3: " << fine
                                              << "), lambda 0.1 " << low << ", lambda 10 "
                                              << high);
  CHECK(low / one == Approx(1).epsilon(0.04));
  CHECK(high / one == Approx(1).epsilon(0.04));
  CHECK(testing::observed_order(one - 1, fine - 1) > 0.8);
}

// lambda 1 (no second-kind solve: cheap enough for two meshes). Measured at level 2,
// Ca 0.025-0.1: D / Ca 1.1017, 1.1031, 1.1086 and [mu] 1.7464, 1.7403, 1.7161, both of
// order 2.0 in Ca; the angle's Ca terms are below its mesh error. Limits Ca -> 0 against
// Taylor and Chaffey-Brenner: level 2 D/Ca +0.7 %, angle -4.7 %, [mu] -0.1 %; level 3
// at Ca 0.05 +0.8 %, -0.7 %, -0.1 % (docs/dilute_limit.md has level 4). Tolerances: the
// orders in Ca within 0.3 of 2 (their spread over lambda at level 2 is 0.1); each limit
// within 1.5 times its level-2 error of the theory, and the angle's mesh order at least 2
// (measured 2.8).
TEST_CASE(
    "drop: at lambda 1 Taylor's D and [mu] and Chaffey-Brenner's angle, second order "
    "in Ca, converging with the mesh",
    "[drop][physics]") {
  const CaSeries coarse = ca_series(0.025, 1, 2);
  const DropValues fine = steady_drop(0.05, 1, 3);
  const double d = taylor_deformation(1), angle = chaffey_brenner_angle(1),
               mu = taylor_viscosity(1);
  INFO("level 2 limits: D/Ca " << coarse.limit.d_over_ca << ", angle/Ca "
                               << coarse.limit.angle_over_ca << ", [mu] "
                               << coarse.limit.mu << "; orders in Ca "
                               << coarse.order.d_over_ca << ", " << coarse.order.mu
                               << "; level 3 at Ca 0.05: " << fine.d_over_ca << ", "
                               << fine.angle_over_ca << ", " << fine.mu);
  CHECK(coarse.order.d_over_ca == Approx(2).margin(0.3));
  CHECK(coarse.order.mu == Approx(2).margin(0.3));
  CHECK(coarse.limit.d_over_ca == Approx(d).epsilon(0.011));
  CHECK(coarse.limit.angle_over_ca == Approx(angle).epsilon(0.07));
  CHECK(coarse.limit.mu == Approx(mu).epsilon(0.0015));
  const double angle_order = std::log(std::abs(coarse.at[1].angle_over_ca / angle - 1) /
                                      std::abs(fine.angle_over_ca / angle - 1)) /
                             std::log(2.0);
  CHECK(angle_order > 2);
  CHECK(std::abs(fine.d_over_ca / d - 1) < std::abs(coarse.at[1].d_over_ca / d - 1));
}
