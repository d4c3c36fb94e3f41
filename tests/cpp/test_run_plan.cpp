// The run plan (run/run_plan.hpp): what a run settles from its options and its backend,
// once; and the one time loop's step, where a fixed step is the controller that accepts
// every step (dynamics/adaptive_step.hpp).
#include "dynamics/adaptive_step.hpp"
#include "mesh/surface_geometry.hpp"
#include "run/automatic_settings.hpp"
#include "run/run_plan.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace capsim;

namespace {

RunPlan plan_of(const std::vector<std::string>& sets) {
  return resolve_run_plan(parse_run_options("", sets), true);
}

const std::vector<std::string> kSuspension = {"phi=0.3", "capsules=2", "mesh_level=1"};

std::vector<std::string> suspension_with(std::vector<std::string> sets) {
  sets.insert(sets.begin(), kSuspension.begin(), kSuspension.end());
  return sets;
}

// Heun's step of dx/dt = -x, whatever error it is told to report; records its times.
struct DecayScheme : Stepper {
  double error = std::nan(""); // a NaN: rejected by any tolerance
  std::vector<double> times;
  double step(std::vector<Vec3>& x, double t, double dt) override {
    times.push_back(t);
    for (Vec3& p : x)
      p = (1 - dt + 0.5 * dt * dt) * p;
    return error;
  }
};

} // namespace

TEST_CASE("run plan: an auto precision is single only where the tolerance allows it and "
          "the backend has it",
          "[plan]") {
  CHECK(resolve_precision(Precision::automatic, 1e-4) == Precision::single_precision);
  CHECK(resolve_precision(Precision::automatic, 1e-6) == Precision::double_precision);
  CHECK(resolve_precision(Precision::automatic, 1e-4, false) ==
        Precision::double_precision);
  // An explicit single stays, for the flow factory to refuse by name on the device.
  CHECK(resolve_precision(Precision::single_precision, 1e-8, false) ==
        Precision::single_precision);

  const RunPlan cpu = plan_of(suspension_with({"ewald.tolerance=1e-4"}));
  CHECK(cpu.backend == Backend::cpu);
  CHECK(cpu.box.grid.single);
  CHECK(cpu.box.ewald.single_real);
  const RunPlan tight = plan_of(suspension_with({"ewald.tolerance=1e-6"}));
  CHECK_FALSE(tight.box.grid.single);
  CHECK_FALSE(tight.box.ewald.single_real);
  // The device has neither single grids nor a single real-space sum, and keeps r_cut
  // below L / 3 (cuda/device_flow.hpp); the plan needs no device to say so.
  const RunPlan cuda = plan_of(suspension_with({"ewald.tolerance=1e-4", "backend=cuda"}));
  CHECK(cuda.backend == Backend::cuda);
  CHECK_FALSE(cuda.box.grid.single);
  CHECK_FALSE(cuda.box.ewald.single_real);
  CHECK(cuda.box.ewald.r_cut < cuda.box.L / 3);
  const RunPlan asked =
      plan_of(suspension_with({"backend=cuda", "ewald.precision=single"}));
  CHECK(asked.box.grid.single);
  // The options keep `auto`: run.yaml and the checkpoint hold what was asked.
  CHECK(cuda.options.ewald.precision == Precision::automatic);
  CHECK(plan_of({}).box.L == 0); // the dilute limit has no box
}

TEST_CASE(
    "run plan: the automatic step of the scheme, its floor, and the outputs counted "
    "in steps of a fixed step or samples of an adaptive one",
    "[plan]") {
  const RunPlan heun = plan_of({"mesh_level=2"});
  const double h = heun.mean_edge;
  CHECK(h == mean_edge_length(heun.mesh.topology, heun.mesh.positions.data()));
  CHECK(heun.time.scheme == TimeScheme::heun);
  CHECK(heun.time.fixed());
  CHECK(heun.time.dt == automatic_time_step(0.2, h, 1.0));
  CHECK(heun.time.min_dt == 1e-6 * heun.time.dt);
  CHECK(heun.output.sample_every == std::lround(0.05 / heun.time.dt));
  // Checkpoints and snapshots fall on samples: whole numbers of them, the nearest to
  // their intervals (1 and 2 strains).
  const long sample = heun.output.sample_every;
  CHECK(heun.output.checkpoint_every ==
        sample * std::lround(1.0 / (sample * heun.time.dt)));
  CHECK(heun.output.snapshot_every ==
        sample * std::lround(2.0 / (sample * heun.time.dt)));

  // A step whose own counts are not multiples of the samples' (11 steps a sample; 222
  // and 444 a checkpoint and a snapshot on their own) still writes every strain or two:
  // 220 and 440 steps (0.99 and 1.98 strains), not once in 2442 and 4884 steps.
  const RunPlan odd = plan_of({"mesh_level=2", "dt=0.0045"});
  CHECK(odd.output.sample_every == 11);
  CHECK(odd.output.checkpoint_every == 220);
  CHECK(odd.output.snapshot_every == 440);

  const RunPlan rkc = plan_of({"mesh_level=2", "time.scheme=rkc", "time.stages=3"});
  CHECK(rkc.time.stages == 3);
  CHECK(rkc.time.dt == heun.time.dt * stability_ratio(TimeScheme::rkc, 3));

  // The viscosity ratio: the mesh-scale waves relax (1 + lambda)/2 times slower, so the
  // step shrinks as much below lambda 1 and grows as much above it, up to dt_lambda_max
  // (by default 1: lambda 1's step).
  const auto step_at = [](const std::string& lambda, const std::string& most) {
    return plan_of({"mesh_level=2", "lambda=" + lambda, "dt_lambda_max=" + most}).time.dt;
  };
  CHECK(step_at("1", "2") == heun.time.dt);
  CHECK(step_at("0.2", "2") == Approx(0.6 * heun.time.dt).epsilon(1e-14));
  CHECK(step_at("2", "2") == Approx(1.5 * heun.time.dt).epsilon(1e-14));
  CHECK(step_at("5", "2") == Approx(2 * heun.time.dt).epsilon(1e-14));
  CHECK(step_at("5", "3") == Approx(3 * heun.time.dt).epsilon(1e-14));
  CHECK(step_at("5", "50") == Approx(3 * heun.time.dt).epsilon(1e-14));
  CHECK(step_at("5", "1") == heun.time.dt); // lambda 1's step, as runs took before
  CHECK(plan_of({"mesh_level=2", "lambda=5"}).time.dt == heun.time.dt);

  const RunPlan given = plan_of({"mesh_level=2", "dt=0.01", "time.tolerance=1e-3",
                                 "time.error_norm=rms", "output.snapshot_interval=0"});
  CHECK(given.time.dt == 0.01);
  CHECK(given.time.min_dt == heun.time.min_dt); // from the automatic step, not dt
  CHECK_FALSE(given.time.fixed());
  CHECK(given.time.norm == ErrorNorm::rms);
  CHECK(given.output.sample_every == 1);
  CHECK(given.output.checkpoint_every == 20);
  CHECK(given.output.snapshot_every == 0);

  // `auto` tolerances resolve in the plan, into the options it writes out.
  const RunPlan imex = plan_of({"time.scheme=imex", "time.tolerance=auto"});
  CHECK(imex.time.tolerance == automatic_time_tolerance(3));
  CHECK(imex.options.time.tolerance == imex.time.tolerance);
  CHECK(plan_of({"time.tolerance=auto"}).time.fixed());
}

TEST_CASE("time stepper: a fixed step is the controller that accepts every step, and "
          "steps as a loop of fixed steps does",
          "[plan]") {
  StepController fixed;
  CHECK(fixed.fixed());
  CHECK(fixed.accept(std::nan("")));
  CHECK(fixed.next(0.1, 1e9) == 0.1);
  CHECK(fixed.size(0.1, 0.35, 0.4) == 0.1); // passes over a target

  const double dt = 0.1, t_end = 1.05;
  DecayScheme scheme, by_hand;
  std::vector<Vec3> x(3, Vec3{1, 2, 3}), y = x;
  TimeStepper clock(scheme, 0, dt, 1e-6, t_end);
  int tries = 0;
  while (!clock.finished()) {
    REQUIRE(clock.step_towards(x, 0.25 * (tries++ + 1)) == StepOutcome::accepted);
    by_hand.step(y, (clock.steps() - 1) * dt, dt);
    CHECK(clock.time() == clock.steps() * dt); // on the grid n dt
  }
  CHECK(clock.steps() == 11); // ceil(t_end / dt); the last passes t_end
  CHECK(clock.rejected() == 0);
  CHECK(clock.dt() == dt);
  CHECK(clock.mean_dt() == dt);
  for (size_t i = 0; i < x.size(); ++i) // the same steps, to the bit
    CHECK((x[i].x == y[i].x && x[i].y == y[i].y && x[i].z == y[i].z));
  for (size_t n = 0; n < scheme.times.size(); ++n)
    CHECK(scheme.times[n] == n * dt);

  // The same scheme under a tolerance rejects its NaN until the step is below its floor.
  TimeStepper adaptive(scheme, 1e-3, dt, 1e-3, t_end);
  StepOutcome outcome = StepOutcome::rejected;
  while (outcome == StepOutcome::rejected)
    outcome = adaptive.step_towards(x, 0.5);
  CHECK(outcome == StepOutcome::failed);
  CHECK(adaptive.steps() == 0);
  CHECK(adaptive.time() == 0);
}

TEST_CASE("time stepper: an adaptive step lands on its target and resumes with the step "
          "saved",
          "[plan]") {
  DecayScheme scheme;
  scheme.error = 1e-5; // well within the tolerance: the step grows
  std::vector<Vec3> x(2, Vec3{1, 0, 0});
  TimeStepper clock(scheme, 1e-3, 0.3, 1e-6, 1.0);
  REQUIRE(clock.step_towards(x, 0.2) == StepOutcome::accepted);
  CHECK(clock.time() == 0.2);
  CHECK(clock.dt() == 0.3); // landing short of dt does not shrink the next step
  REQUIRE(clock.step_towards(x, 1.0) == StepOutcome::accepted);
  CHECK(clock.time() == Approx(0.5));
  CHECK(clock.dt() == Approx(0.6));
  TimeStepper resumed(scheme, 1e-3, 0.3, 1e-6, 1.0);
  resumed.resume(clock.steps(), clock.time(), clock.dt(), 4);
  CHECK(resumed.time() == clock.time());
  CHECK(resumed.dt() == clock.dt());
  CHECK(resumed.rejected() == 4);
  TimeStepper fixed(scheme, 0, 0.3, 1e-6, 1.0);
  fixed.resume(2, 0.6, 0.17, 0); // a fixed step keeps its dt and grid
  CHECK(fixed.dt() == 0.3);
  CHECK(fixed.time() == 2 * 0.3);
  // A grid from step 5 at 0.55 (a branch's checkpoint): 0.85 after one step, and t_end
  // 1.0 after two (1.15; the last may pass it).
  TimeStepper moved(scheme, 0, 0.3, 1e-6, 1.0);
  moved.resume(5, 0.55, 0, 0, {5, 0.55});
  CHECK(moved.time() == 0.55);
  REQUIRE(moved.step_towards(x, 1.0) == StepOutcome::accepted);
  CHECK(moved.time() == 0.55 + 0.3);
  CHECK(moved.grid_steps() == 1);
  CHECK_FALSE(moved.finished());
  REQUIRE(moved.step_towards(x, 1.0) == StepOutcome::accepted);
  CHECK(moved.finished());
  CHECK(moved.steps() == 7);
}
