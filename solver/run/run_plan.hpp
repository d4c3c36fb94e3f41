#pragma once
// The run plan: everything a run settles from its options and its backend's declared
// capabilities, resolved once before anything is built or written, then only read (the
// time loop, summary.json, `capsim bench`'s box). Each choice key is its enum already
// (config/run_options.hpp); here each `auto` gets its value: the tolerances
// (run/automatic_settings.hpp), the precisions of the periodic sums against the
// backend, the box, the step and its floor, and how often the outputs come.
#include "config/run_options.hpp"
#include "dynamics/flow.hpp"
#include "mesh/icosphere.hpp"

#include <string>

namespace capsim {

struct TimePlan {
  TimeScheme scheme = TimeScheme::heun;
  int stages = 4; // of rkc
  ErrorNorm norm = ErrorNorm::max;
  double tolerance = 0; // of the adaptive step; 0: a fixed step
  double dt = 0;        // the fixed step, or the first adaptive one
  double min_dt = 0;    // the floor of an adaptive step (below it the state is broken)
  double t_end = 0;
  bool fixed() const { return tolerance <= 0; }
};

// Outputs every so many steps of a fixed step, or samples of an adaptive one (whose
// steps land on every sample time); checkpoint_every and snapshot_every are whole
// multiples of sample_every (they are written at samples); snapshot_every 0: none.
struct OutputPlan {
  long sample_every = 0, checkpoint_every = 0, snapshot_every = 0;
};

struct RunPlan {
  RunOptions options; // `auto` tolerances resolved, as run.yaml and checkpoints hold them
  Icosphere mesh;     // the undeformed capsule
  double mean_edge = 0; // h of the mesh: sets the automatic step
  Backend backend = Backend::cpu;
  PeriodicBox box; // L = 0 in the dilute limit; its precisions single or double
  TimePlan time;
  OutputPlan output;
};

// The plan of `options`, saying on stderr (unless quiet) what the `auto` tolerances
// became. Throws ConfigError naming the key when the options cannot make a plan (a given
// ewald.xi out of proportion to the box).
RunPlan resolve_run_plan(const RunOptions& options, bool quiet);

// The periodic box of side L for `request` evaluated with `caps`: an `auto` precision
// becomes single only where the backend has it (an explicit single stays, for the flow
// factory to refuse by name), and xi stays within the backend's cut-off. A given xi out
// of proportion to the box throws ConfigError prefixed with `xi_key`.
PeriodicBox plan_periodic_box(double L, EwaldOptions request,
                              const FlowCapabilities& caps, long nodes, long points,
                              const std::string& xi_key);

// What the flow of the plan needs, around `membrane` (which must outlive it).
FlowSetup flow_setup(const RunPlan& plan, const Membrane& membrane);

} // namespace capsim
