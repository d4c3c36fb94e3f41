#pragma once
// Where a run's time goes, measured in the run itself (`capsim run --profile FILE`): the
// wall seconds of every stage of its steps, from the flow's evaluations (membrane load,
// near corrections, real space, spreading, FFT, gathering) to the outputs (sampling,
// checkpoints), so that a stage out of line shows at the scale the workflow runs.
#include "dynamics/flow.hpp"

#include <omp.h>
#include <string>

namespace capsim {

struct RunProfile {
  FlowProfile flow;
  long steps = 0;      // accepted steps
  double stepping = 0; // the time scheme's steps, the flow's evaluations within
  double volume_constraint = 0;
  double state_checks = 0;    // inverted triangles, finite positions
  double box_and_contact = 0; // Lees-Edwards remapping and the contact check
  double sampling = 0;        // the diagnostics of one row of the time series
  double snapshots = 0;
  double checkpoints = 0; // the time series rows written and the checkpoint
  double loop = 0;        // the whole time loop
};

// Adds the wall seconds of its scope to *into; does nothing when into is null (a run
// without a profile).
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

// FILE: JSON with every stage in seconds per step and in total, and the evaluations'
// counts (benchmarks/step_profile.py reads it).
void write_run_profile(const std::string& path, const RunProfile& p);

} // namespace capsim
