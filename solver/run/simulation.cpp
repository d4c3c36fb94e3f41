#include "run/simulation.hpp"

#include "common/suspension.hpp"
#include "diagnostics/averages.hpp"
#include "diagnostics/capsule_diagnostics.hpp"
#include "diagnostics/snapshot_fields.hpp"
#include "dynamics/adaptive_step.hpp"
#include "dynamics/lees_edwards.hpp"
#include "dynamics/packing.hpp"
#include "dynamics/state_checks.hpp"
#include "dynamics/time_schemes.hpp"
#include "dynamics/volume_constraint.hpp"
#include "membrane/compression.hpp"
#include "mesh/surface_geometry.hpp"
#include "run/automatic_settings.hpp"
#include "run/flow_factory.hpp"
#include "run/progress.hpp"
#include "run/run_files.hpp"
#include "run/step_failure.hpp"
#include "run/summary.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <omp.h>

namespace capsim {

bool may_change_on_resume(const std::string& key) {
  return key == "t_end" || key == "t_avg_start" || key == "threads" || key == "backend" ||
         key.rfind("output.", 0) == 0;
}

namespace {

using Clock = std::chrono::steady_clock;

// The automatic step of the run's scheme: Heun's (automatic_time_step) times how much
// longer a step the scheme's stability allows (rkc: beta(s) / 2).
double automatic_step(const RunOptions& o, double h) {
  return automatic_time_step(o.ca, h, o.dt_safety, o.bending) *
         stability_ratio(parse_time_scheme(o.time.scheme), o.time.stages);
}

// The periodic box for phi > 0 (docs/conventions.md), within what the backend can
// evaluate; none (L = 0) in the dilute limit.
PeriodicBox periodic_box(const RunOptions& o, const Topology& topo) {
  if (o.phi <= 0)
    return {};
  EwaldOptions r = o.ewald;
  const FlowCapabilities caps = capabilities_of(parse_backend(o.backend));
  // auto chooses among what the backend has: double where it has no single grids (an
  // explicit single is refused there by unsupported_by, naming the key).
  if (r.precision == Precision::automatic && !caps.single_grids)
    r.precision = Precision::double_precision;
  if (r.real_space_precision == Precision::automatic && !caps.single_real_space)
    r.real_space_precision = Precision::double_precision;
  const long nodes = long(o.capsules) * topo.num_nodes;
  const long points = far_rule_points(topo, o.capsules);
  try {
    return make_periodic_box(periodic_box_side(o.capsules, o.phi), r, nodes, points,
                             caps.max_cut_fraction);
  } catch (const std::invalid_argument& e) { // a given xi out of proportion to the box
    throw ConfigError(std::string("ewald.xi: ") + e.what());
  }
}

FlowSetup flow_setup(const RunOptions& o, const Membrane& membrane,
                     const PeriodicBox& box) {
  FlowSetup s(membrane, o.capsules, o.flow == "shear" ? 1.0 : 0.0);
  s.load = o.load;
  s.quadrature = o.quadrature;
  s.box = box;
  s.repulsion = o.suspension.repulsion;
  return s;
}

// Adds the wall seconds of its scope to *into; does nothing when into is null.
class ScopeTimer {
public:
  explicit ScopeTimer(double* into) : into_(into), start_(into ? omp_get_wtime() : 0) {}
  ~ScopeTimer() {
    if (into_)
      *into_ += omp_get_wtime() - start_;
  }
  ScopeTimer(const ScopeTimer&) = delete;
  ScopeTimer& operator=(const ScopeTimer&) = delete;

private:
  double* into_;
  double start_;
};

long steps_for(double interval, double dt) {
  return interval > 0 ? std::max(1L, std::lround(interval / dt)) : 0;
}

class RunLoop {
public:
  RunLoop(const RunOptions& o, std::string dir, bool quiet, double pause_at,
          RunProfile* profile)
      : o_(o), files_(std::move(dir), o.capsules), progress_(quiet, o.t_end),
        pause_at_(pause_at), profile_(profile), mesh_(make_icosphere(o.mesh_level)),
        membrane_(mesh_.topology, mesh_.positions.data(), 1.0 / o.ca, o.bending / o.ca,
                  o.wrinkling),
        h_(mean_edge_length(mesh_.topology, mesh_.positions.data())),
        dt_(o.dt > 0 ? o.dt : automatic_step(o, h_)),
        flow_(make_flow(parse_backend(o.backend),
                        flow_setup(o, membrane_, periodic_box(o, mesh_.topology)))),
        stepper_(make_stepper(parse_time_scheme(o.time.scheme), *flow_,
                              parse_error_norm(o.time.error_norm), o.time.stages)),
        // An adaptive step a millionth of the automatic one means a broken state.
        adaptive_(*stepper_, o.time.tolerance, dt_, 1e-6 * automatic_step(o, h_)) {
    // A fixed step counts steps between outputs; an adaptive one counts samples.
    const double unit = adaptive() ? o.output.sample_interval : dt_;
    n_steps_ = std::lround(std::ceil(o.t_end / dt_ - 1e-9));
    sample_every_ = steps_for(o.output.sample_interval, unit);
    checkpoint_every_ = steps_for(o.output.checkpoint_interval, unit);
    snapshot_every_ = steps_for(o.output.snapshot_interval, unit);
    v0_.assign(o.capsules, enclosed_volume(mesh_.topology, mesh_.positions.data()));
    drift_.assign(o.capsules, 0.0);
    if (profile_)
      flow_->attach_profile(&profile_->flow);
  }

  void start_fresh();
  void check_series(const Checkpoint& c) const { files_.check_series(c); }
  void start_from(const Checkpoint& c);
  std::string resume_hint() const { return files_.resume_hint(); }
  void run();
  bool paused() const { return paused_; }
  // summary.json; `ended` is "t_end" or the SimulationError kind that stopped the run.
  void write_summary(double wall_seconds, bool resumed,
                     const std::string& ended = "t_end",
                     const std::string& end_message = "") const;

private:
  void take_sample();
  void save_checkpoint();
  void save_snapshot();
  void report_progress(bool force);
  void keep_in_box();
  void step_until_end();
  void step_adaptively();
  bool try_step(double target);
  void finish_step();
  void write_outputs(long index, bool sample, bool last);
  bool adaptive() const { return o_.time.tolerance > 0; }
  // gammadot t: step * dt exactly for a fixed step, so a resumed run stays on its grid.
  double time() const { return adaptive() ? t_ : step_ * dt_; }
  // The fixed step, or the adaptive step to try next.
  double next_dt() const { return adaptive() ? adaptive_.dt() : dt_; }
  const PeriodicBox& box() const { return flow_->setup().box; }

  RunOptions o_;
  RunFiles files_;
  ProgressReport progress_;
  double pause_at_;     // RunRequest::pause_at
  bool paused_ = false; // stopped at pause_at_, after a regular checkpoint
  RunProfile* profile_; // RunRequest::profile (null: none)
  // The profile's accumulator of one stage, or null without a profile (ScopeTimer).
  double* stage(double RunProfile::*field) const {
    return profile_ ? &(profile_->*field) : nullptr;
  }
  Icosphere mesh_;
  Membrane membrane_;
  double h_;  // mean edge of the undeformed mesh: sets dt
  double dt_; // the fixed step, or the first adaptive one
  std::unique_ptr<Flow> flow_;
  std::unique_ptr<Stepper> stepper_;
  AdaptiveStepper adaptive_; // steps with time.tolerance > 0
  double t_ = 0;             // gammadot t of an adaptive run
  long n_steps_, sample_every_, checkpoint_every_, snapshot_every_;
  long step_ = 0;
  std::vector<Vec3> x_;
  std::vector<double> v0_, drift_;
};

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
    for (const auto& p : mesh_.positions)
      x_.push_back(c + Vec3{s * p.x, p.y / std::sqrt(s), p.z / std::sqrt(s)});
  files_.start(o_);
  take_sample();
  if (snapshot_every_ > 0)
    save_snapshot();
  save_checkpoint();
}

void RunLoop::start_from(const Checkpoint& c) {
  if (c.nodes_per_capsule != mesh_.topology.num_nodes || c.num_capsules != o_.capsules)
    throw ConfigError(
        "checkpoint in '" + files_.dir() + "' does not match its own options " +
        "(mesh or capsule count differ): it is not a capsim checkpoint of this run");
  // Every saved state passed check_state; one that does not now was altered since.
  const std::string problem = broken_state(mesh_.topology, o_.capsules, c.positions);
  if (!problem.empty())
    throw std::runtime_error("checkpoint " + files_.dir() +
                             "/checkpoint.h5 is corrupt: " + "/positions " + problem);
  x_ = c.positions;
  v0_ = c.volume0;
  step_ = c.step;
  t_ = c.time;
  adaptive_.set_rejected(c.rejected_steps);
  if (adaptive() && c.next_dt > 0)
    adaptive_.set_dt(c.next_dt);
  files_.resume(c, o_);
}

// A SimulationError leaves the loop with the samples taken since the last checkpoint
// written to the time series (they are states that passed every check), so summary.json
// can average up to the stop; a resume drops them again with the rest after the
// checkpoint.
void RunLoop::run() {
  progress_.start(time(), step_);
  ScopeTimer loop(stage(&RunProfile::loop));
  try {
    step_until_end();
  } catch (const SimulationError&) {
    files_.flush_samples();
    throw;
  }
}

void RunLoop::step_until_end() {
  if (adaptive())
    return step_adaptively();
  while (step_ < n_steps_ && !paused_) {
    {
      ScopeTimer timer(stage(&RunProfile::stepping));
      stepper_->step(x_, time(), dt_);
    }
    ++step_;
    finish_step();
    const bool last = step_ == n_steps_;
    write_outputs(step_, step_ % sample_every_ == 0 || last, last);
    report_progress(last);
  }
}

// Steps end on every sample time k * output.sample_interval and on t_end, so the time
// series keeps its spacing; outputs are counted in samples.
void RunLoop::step_adaptively() {
  const double interval = o_.output.sample_interval;
  while (t_ < o_.t_end && !paused_) {
    const long next_sample = files_.samples();
    const double target = std::min(o_.t_end, next_sample * interval);
    if (!try_step(target))
      continue;
    finish_step();
    const bool last = t_ >= o_.t_end;
    write_outputs(next_sample, t_ == target, last);
    report_progress(last);
  }
}

// One adaptive step towards `target` (dynamics/adaptive_step.hpp); false when its error
// estimate rejected it (x_ and t_ stay, the step shrinks).
bool RunLoop::try_step(double target) {
  StepOutcome outcome;
  {
    ScopeTimer timer(stage(&RunProfile::stepping));
    outcome = adaptive_.step_towards(x_, t_, target);
  }
  if (outcome == StepOutcome::failed)
    throw SimulationError("at gammadot*t = " + std::to_string(t_) +
                          " the adaptive step fell to " + std::to_string(adaptive_.dt()) +
                          " without meeting time.tolerance: the state is broken (the "
                          "output folder keeps the last good checkpoint)");
  if (outcome == StepOutcome::rejected)
    return false;
  ++step_;
  return true;
}

// The volume constraint, the checks, and the Lees-Edwards remapping after a step.
void RunLoop::finish_step() {
  if (profile_)
    ++profile_->steps;
  {
    ScopeTimer timer(stage(&RunProfile::volume_constraint));
    std::vector<double> d = enforce_volume(mesh_.topology, o_.capsules, x_, v0_);
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

// After step (fixed) or sample (adaptive) number `index`.
void RunLoop::write_outputs(long index, bool sample, bool last) {
  if (sample) {
    ScopeTimer timer(stage(&RunProfile::sampling));
    take_sample();
  }
  if (sample && snapshot_every_ > 0 && index % snapshot_every_ == 0) {
    ScopeTimer timer(stage(&RunProfile::snapshots));
    save_snapshot();
  }
  if ((sample && index % checkpoint_every_ == 0) || last) {
    ScopeTimer timer(stage(&RunProfile::checkpoints));
    save_checkpoint();
  }
  // Only at a regular checkpoint: the unbroken run writes the same one, so a resumed
  // segment continues it to the last bit (a checkpoint forced at `last` would add a row).
  if (!last && pause_at_ > 0 && files_.checkpoint_time() == time() && time() >= pause_at_)
    paused_ = true;
}

// Lees-Edwards remapping, then the contact check: capsules may not interpenetrate.
void RunLoop::keep_in_box() {
  const ShearedLattice lattice = flow_->lattice(time());
  remap_capsules(mesh_.topology, o_.capsules, lattice, x_);
  ClosestApproach c = closest_approach(mesh_.topology, o_.capsules, lattice, x_,
                                       o_.suspension.stop_distance);
  if (!(c.distance < o_.suspension.stop_distance))
    return;
  const std::string who =
      c.capsule_a == c.capsule_b
          ? "capsule " + std::to_string(c.capsule_a) + " and its periodic image touch"
          : "capsules " + std::to_string(c.capsule_a) + " and " +
                std::to_string(c.capsule_b) + " touch";
  throw SimulationError(who + " at gammadot*t = " + std::to_string(time()) +
                            " (node distance " + std::to_string(c.distance) +
                            " < suspension.stop_distance): the near-contact "
                            "flow is under-resolved; start again with a smaller dt or a "
                            "finer mesh (the output "
                            "folder keeps the last good checkpoint and time series)",
                        "contact");
}

void RunLoop::take_sample() {
  std::vector<Vec3> grad;
  std::vector<double> energy = flow_->energy_gradient(x_, grad);
  const int nn = mesh_.topology.num_nodes;
  Sample s;
  s.time = time();
  s.step = step_;
  // The stresslet sees the whole load on the membrane, the repulsion's included.
  const std::vector<int> repelled = flow_->add_repulsion(x_, s.time, grad);
  for (int c = 0; c < o_.capsules; ++c) {
    s.capsules.push_back(capsule_sample(mesh_.topology, &x_[c * nn], &grad[c * nn],
                                        energy[c], v0_[c], o_.ca));
    s.capsules.back().volume_drift = drift_[c];
    s.capsules.back().repelled_nodes = repelled[c];
    const Compression k =
        compression(membrane_.neo_hookean_element_tensions(&x_[c * nn]));
    s.capsules.back().compressed_elements = k.elements;
    s.capsules.back().min_tension = k.min_tension;
    drift_[c] = 0;
  }
  files_.add_sample(std::move(s));
}

void RunLoop::save_checkpoint() {
  Checkpoint c;
  c.time = time();
  c.next_dt = next_dt();
  c.rejected_steps = adaptive_.rejected();
  c.step = step_;
  c.num_capsules = o_.capsules;
  c.nodes_per_capsule = mesh_.topology.num_nodes;
  c.volume0 = v0_;
  c.positions = x_;
  c.options_yaml = to_yaml(o_);
  files_.save_checkpoint(c);
}

void RunLoop::save_snapshot() {
  SnapshotFrame frame;
  frame.time = time();
  if (flow_->periodic()) {
    frame.box_side = box().L;
    frame.strain = flow_->lattice(frame.time).s;
  }
  // Velocity and traction (one more evaluation of the flow: one per snapshot, against
  // two per step), and the membrane's tensions (diagnostics/snapshot_fields.hpp).
  flow_->velocity(x_, frame.time, frame.velocity);
  flow_->traction(x_, frame.time, frame.traction);
  add_membrane_fields(membrane_, o_.capsules, x_, frame);
  files_.save_snapshot(frame, mesh_.topology.triangles, x_);
}

void RunLoop::report_progress(bool force) {
  progress_.report(time(), step_, next_dt(), adaptive() ? adaptive_.rejected() : -1,
                   force);
}

void RunLoop::write_summary(double wall_seconds, bool resumed, const std::string& ended,
                            const std::string& end_message) const {
  std::vector<Sample> samples = files_.read_series();
  SummaryFacts facts;
  facts.ended = ended;
  facts.end_message = end_message;
  facts.dt =
      adaptive() && step_ > 0 ? time() / step_ : next_dt(); // the mean, if adaptive
  facts.rejected_steps = adaptive_.rejected();
  facts.mean_edge = h_;
  facts.steps = step_;
  facts.wall_seconds = wall_seconds;
  // The cost measure of the accuracy study: CPU time is steadier than wall time on a
  // shared machine, and counts every thread.
  facts.cpu_seconds = static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
  facts.resumed = resumed;
  facts.threads = omp_get_max_threads();
  facts.box_side = box().L;
  facts.ewald_xi = box().ewald.xi;
  facts.ewald_r_cut = box().ewald.r_cut;
  facts.ewald_k_cut = box().ewald.k_cut;
  auto precision = [](bool single) {
    return to_string(single ? Precision::single_precision : Precision::double_precision);
  };
  if (box().method == EwaldMethod::spectral) {
    facts.spectral_grid.assign(box().grid.grid, box().grid.grid + 3);
    facts.spectral_precision = precision(box().grid.single);
  }
  facts.spectral_support = box().grid.support;
  facts.real_space_precision = precision(box().ewald.single_real);
  double t_final = samples.empty() ? 0.0 : samples.back().time;
  write_summary_json(files_.dir() + "/summary.json", o_,
                     time_average(samples, o_.t_avg_start, t_final), facts);
}

RunOptions resume_options(const std::string& dir, const Checkpoint& c,
                          const std::vector<std::string>& overrides) {
  for (const auto& s : overrides) {
    std::string key = s.substr(0, s.find('='));
    if (!may_change_on_resume(key))
      throw ConfigError(
          "--set " + key +
          ": cannot change on --resume (it would change the "
          "steps already taken); only t_end, t_avg_start, threads, backend and "
          "output.* "
          "can. Start a new run for other values");
  }
  return parse_run_options(c.options_yaml, overrides, "checkpoint in " + dir);
}

// The run after its set-up, to summary.json; a numerical stop records how it ended.
bool run_to_end(RunLoop& loop, const RunRequest& request, Clock::time_point begin,
                const Checkpoint& checkpoint) {
  if (request.resume)
    loop.start_from(checkpoint);
  else
    loop.start_fresh();
  auto seconds = [&] {
    return std::chrono::duration<double>(Clock::now() - begin).count();
  };
  try {
    loop.run();
  } catch (const SimulationError& e) {
    loop.write_summary(seconds(), request.resume, e.kind, e.what());
    throw;
  }
  if (loop.paused())
    return false;
  loop.write_summary(seconds(), request.resume);
  return true;
}

} // namespace

bool run_simulation(const RunRequest& request) {
  const auto begin = Clock::now();
  RunOptions o = request.options;
  Checkpoint checkpoint;
  if (request.resume) {
    checkpoint = read_checkpoint(request.outdir + "/checkpoint.h5");
    o = resume_options(request.outdir, checkpoint, request.resume_overrides);
  }
  resolve_automatic_settings(o, request.quiet);
  if (o.threads > 0)
    omp_set_num_threads(o.threads);
  // Built first: a backend that cannot run the options stops the run before anything
  // is written.
  RunLoop loop(o, request.outdir, request.quiet, request.pause_at, request.profile);
  if (request.resume)
    loop.check_series(checkpoint);
  else
    RunFiles::prepare_fresh(request.outdir);
  // A failed write (a full disk, a read-only folder) says which file and what failed,
  // then where the run can continue from.
  try {
    return run_to_end(loop, request, begin, checkpoint);
  } catch (const ConfigError&) {
    throw;
  } catch (const SimulationError&) {
    throw;
  } catch (const std::exception& e) {
    throw std::runtime_error(e.what() + loop.resume_hint());
  }
}

} // namespace capsim
