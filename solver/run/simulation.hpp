#pragma once
// The run loop behind `capsim run`: set up the capsule(s), step in time, write samples,
// checkpoints and snapshots, and finally summary.json. Orchestration only: the physics is
// in mesh/, membrane/, stokes/, dynamics/ and diagnostics/.
#include "config/run_options.hpp"

#include <string>
#include <vector>

namespace capsim {

struct RunRequest {
  RunOptions options; // ignored when resuming: the checkpoint's options are used
  std::string outdir;
  bool resume = false;
  std::vector<std::string> resume_overrides; // key=value allowed when resuming
  bool quiet = false;                        // no progress lines
};

// Runs to t_end and writes OUTDIR/summary.json. Throws ConfigError for bad input and
// SimulationError for a numerical failure; the last good checkpoint stays in either case.
void run_simulation(const RunRequest& request);

// Keys that may change on --resume: they do not alter the physics of the steps taken.
bool may_change_on_resume(const std::string& key);

} // namespace capsim
