#include "run/run_loop.hpp"

#include "dynamics/packing.hpp"
#include "dynamics/simulation_error.hpp"
#include "dynamics/volume_constraint.hpp"
#include "mesh/surface_geometry.hpp"
#include "run/flow_factory.hpp"
#include "run/step_failure.hpp"

#include <algorithm>
#include <cmath>

namespace capsim {

RunLoop::RunLoop(const RunPlan& plan, std::string dir, bool quiet, double pause_at,
                 RunProfile* profile)
    : plan_(plan), o_(plan.options), files_(std::move(dir), o_.capsules),
      progress_(quiet, o_.t_end), pause_at_(pause_at), profile_(profile),
      membrane_(plan.mesh.topology, plan.mesh.positions.data(), 1.0 / o_.ca,
                o_.bending / o_.ca, o_.wrinkling, o_.law),
      flow_(make_flow(plan.backend, flow_setup(plan, membrane_))),
      scheme_(make_stepper(plan.time.scheme, *flow_, plan.time.norm, plan.time.stages)),
      clock_(*scheme_, plan.time.tolerance, plan.time.dt, plan.time.min_dt,
             plan.time.t_end) {
  v0_.assign(o_.capsules, enclosed_volume(topology(), plan.mesh.positions.data()));
  drift_.assign(o_.capsules, 0.0);
  if (profile_)
    flow_->attach_profile(&profile_->flow);
}

void RunLoop::start_fresh() {
  const double s = o_.initial_stretch;
  std::vector<Vec3> centres(1); // the dilute limit: one capsule at the origin
  if (flow_->periodic()) {
    PackingOptions pack;
    pack.capsules = o_.capsules;
    pack.box = box().L;
    pack.min_gap = o_.suspension.min_gap;
    pack.seed = unsigned(o_.seed);
    try {
      centres = pack_spheres(pack);
    } catch (const std::runtime_error& e) {
      throw ConfigError(std::string("phi: ") + e.what());
    }
  }
  x_.clear();
  for (const Vec3& c : centres)
    for (const auto& p : plan_.mesh.positions)
      x_.push_back(c + Vec3{s * p.x, p.y / std::sqrt(s), p.z / std::sqrt(s)});
  files_.start(o_);
  take_sample();
  if (plan_.output.snapshot_every > 0)
    save_snapshot();
  save_checkpoint();
}

void RunLoop::start_from(const Checkpoint& c) {
  if (c.nodes_per_capsule != topology().num_nodes || c.num_capsules != o_.capsules)
    throw ConfigError(
        "checkpoint in '" + files_.dir() + "' does not match its own options " +
        "(mesh or capsule count differ): it is not a capsim checkpoint of this run");
  // Every saved state passed check_state; one that does not now was altered since.
  const std::string problem = broken_state(topology(), o_.capsules, c.positions);
  if (!problem.empty())
    throw std::runtime_error("checkpoint " + files_.dir() +
                             "/checkpoint.h5 is corrupt: " + "/positions " + problem);
  x_ = c.positions;
  v0_ = c.volume0;
  clock_.resume(c.step, c.time, c.next_dt, c.rejected_steps,
                {long(c.step_origin_index), c.step_origin_time});
  files_.resume(c, o_);
  sample_origin_time_ = c.sample_origin_time;
  sample_origin_index_ = long(c.sample_origin_index);
  // A checkpoint is written at a sample. Where that sample is not on this run's grid (an
  // adaptive branch from a fixed step, or a resume with another output.sample_interval),
  // the grid starts again there, so that no sample falls before the checkpoint.
  const long last = long(c.samples_written) - 1;
  if (!clock_.fixed() && last >= 0 && sample_time(last) != c.time) {
    sample_origin_time_ = c.time;
    sample_origin_index_ = last;
  }
}

// A SimulationError leaves the loop with the samples taken since the last checkpoint
// written to the time series (they are states that passed every check), so summary.json
// can average up to the stop; a resume drops them again with the rest after the
// checkpoint.
void RunLoop::run() {
  progress_.start(time(), clock_.steps());
  ScopeTimer loop(stage(&RunProfile::loop));
  try {
    step_until_end();
  } catch (const SimulationError&) {
    files_.flush_samples();
    throw;
  }
}

// The one time loop. Each step is aimed at the next sample time: an adaptive step lands
// on it, so the time series keeps its spacing; a fixed step passes over it on its grid.
void RunLoop::step_until_end() {
  while (!clock_.finished() && !paused_) {
    const long next_sample = files_.samples();
    const double target = std::min(o_.t_end, sample_time(next_sample));
    if (!try_step(target))
      continue;
    finish_step();
    write_outputs(next_sample, target);
    report_progress(clock_.finished());
  }
}

// One step towards `target` (dynamics/adaptive_step.hpp); false when its error estimate
// rejected it (x_ and the time stay, the step shrinks).
bool RunLoop::try_step(double target) {
  StepOutcome outcome;
  {
    ScopeTimer timer(stage(&RunProfile::stepping));
    outcome = clock_.step_towards(x_, target);
  }
  if (outcome == StepOutcome::failed)
    throw SimulationError("at gammadot*t = " + std::to_string(time()) +
                          " the adaptive step fell to " + std::to_string(clock_.dt()) +
                          " without meeting time.tolerance: the state is broken (the "
                          "output folder keeps the last good checkpoint)");
  return outcome == StepOutcome::accepted;
}

// The volume constraint, the checks, and the Lees-Edwards remapping after a step.
void RunLoop::finish_step() {
  if (profile_)
    ++profile_->steps;
  {
    ScopeTimer timer(stage(&RunProfile::volume_constraint));
    std::vector<double> d = enforce_volume(topology(), o_.capsules, x_, v0_);
    for (int c = 0; c < o_.capsules; ++c)
      if (std::abs(d[c]) > std::abs(drift_[c]))
        drift_[c] = d[c];
  }
  {
    ScopeTimer timer(stage(&RunProfile::state_checks));
    check_state(membrane_, o_.capsules, x_, time());
  }
  ScopeTimer timer(stage(&RunProfile::box_and_contact));
  if (flow_->periodic())
    keep_in_box();
}

// Lees-Edwards remapping, then the contact check: capsules may not interpenetrate.
void RunLoop::keep_in_box() {
  const ShearedLattice lattice = flow_->lattice(time());
  remap_capsules(topology(), o_.capsules, lattice, x_);
  check_contact(topology(), o_.capsules, lattice, x_, o_.suspension.stop_distance,
                time());
}

void RunLoop::report_progress(bool force) {
  progress_.report(time(), clock_.steps(), clock_.dt(),
                   clock_.fixed() ? -1 : clock_.rejected(), force);
}

} // namespace capsim
