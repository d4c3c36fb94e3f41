#pragma once
// The tolerances a run may leave to 'auto', chosen so that neither the Ewald sums nor the
// adaptive step adds more than a tenth of the mesh's discretisation error at the run's
// mesh level. The error models and their measured constants are in docs/method.md
// ("Settings that fit the scene"), measured by the workflow's accuracy study.
#include "config/run_options.hpp"
#include "dynamics/step_error.hpp"

namespace capsim {

double automatic_ewald_tolerance(int mesh_level);
// Of the imex scheme; the rms norm's time error is larger at equal tolerance.
double automatic_time_tolerance(int mesh_level, ErrorNorm norm = ErrorNorm::max);

// Replaces each 'auto' tolerance by its value (time.tolerance of heun: 0, a fixed step)
// and says so on stderr unless quiet, so that run.yaml, the checkpoint and summary.json
// hold the values the run used.
void resolve_automatic_settings(RunOptions& o, bool quiet);

} // namespace capsim
