#pragma once
// The run loop behind `capsim run`: set up the capsule(s), step in time, write samples,
// checkpoints and snapshots, and finally summary.json. Orchestration only: the physics is
// in mesh/, membrane/, stokes/, dynamics/ and diagnostics/.
#include "config/run_options.hpp"
#include "run/run_profile.hpp"

#include <string>
#include <vector>

namespace capsim {

struct RunRequest {
  RunOptions options; // ignored when resuming: the checkpoint's options are used
  std::string outdir;
  bool resume = false;
  std::vector<std::string> resume_overrides; // key=value allowed when resuming
  // Non-empty: a new run in outdir from the last checkpoint of the run in this folder
  // (its state, time and time series up to there), with resume_overrides, which may
  // change the numerical settings too (may_change_on_branch). resume stays false.
  std::string branch_from;
  bool quiet = false; // no progress lines
  // > 0: pause at the first regular checkpoint at or after gammadot t = pause_at (one
  // segment of a longer run): no summary.json, and --resume continues exactly as if the
  // run had never stopped, since the pause falls where the unbroken run checkpoints too.
  double pause_at = 0;
  RunProfile* profile = nullptr; // accumulates where the time goes (run/run_profile.hpp)
};

// Runs to t_end (or to the pause) and writes OUTDIR/summary.json (not when paused).
// Throws ConfigError for bad input and SimulationError for a numerical failure; the last
// good checkpoint stays in either case. Returns false when the run paused before t_end.
bool run_simulation(const RunRequest& request);

// Keys that may change on --resume: they do not alter the physics of the steps taken.
bool may_change_on_resume(const std::string& key);

// Keys that may change on --branch: those of --resume and the numerical settings (time
// scheme and step, Ewald, quadrature, GMRES): a branch continues the same model with
// other numerics, e.g. to compare time schemes from a developed suspension.
bool may_change_on_branch(const std::string& key);

} // namespace capsim
