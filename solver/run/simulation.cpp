#include "run/simulation.hpp"

#include "dynamics/simulation_error.hpp"
#include "run/run_loop.hpp"
#include "run/run_plan.hpp"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <omp.h>
#include <utility>

namespace capsim {

bool may_change_on_resume(const std::string& key) {
  return key == "t_end" || key == "t_avg_start" || key == "threads" || key == "backend" ||
         key.rfind("output.", 0) == 0;
}

bool may_change_on_branch(const std::string& key) {
  static const char* const numerical[] = {"time.", "ewald.", "quadrature.", "gmres."};
  return may_change_on_resume(key) || key == "method" || key == "dt" ||
         key == "dt_safety" || key == "dt_lambda_max" ||
         std::any_of(std::begin(numerical), std::end(numerical),
                     [&](const char* prefix) { return key.rfind(prefix, 0) == 0; });
}

namespace {

using Clock = std::chrono::steady_clock;

// Refuses the first --set key that `may_change` does not allow: "--set KEY: " + why.
void check_overrides(const std::vector<std::string>& overrides,
                     bool (*may_change)(const std::string&), const std::string& why) {
  for (const auto& s : overrides) {
    const std::string key = s.substr(0, s.find('='));
    if (!may_change(key))
      throw ConfigError("--set " + key + ": " + why);
  }
}

RunOptions resume_options(const std::string& dir, const Checkpoint& c,
                          const std::vector<std::string>& overrides) {
  check_overrides(overrides, may_change_on_resume,
                  "cannot change on --resume (it would change the steps already taken); "
                  "only t_end, t_avg_start, threads, backend and output.* can. Start a "
                  "new run for other values, or --branch for other numerics");
  return parse_checkpoint_options(c.options_yaml, overrides, "checkpoint in " + dir);
}

// A branch keeps the model (Ca, phi, membrane, lambda, mesh, ...) and may take other
// numerics, a fixed step of another size included: that step's grid starts at the
// checkpoint's time (RunLoop::start_from), so a step compared with another from a
// developed state needs no run from rest.
RunOptions branch_options(const std::string& dir, const Checkpoint& c,
                          const std::vector<std::string>& overrides) {
  check_overrides(
      overrides, may_change_on_branch,
      "cannot change on --branch (it is the model, not the numerics); only "
      "the keys of --resume, method, dt, dt_safety, dt_lambda_max, time.*, ewald.*, "
      "quadrature.* and gmres.* can. Start a new run for other values");
  return parse_checkpoint_options(c.options_yaml, overrides, "checkpoint in " + dir);
}

// The run after its set-up, to summary.json; a numerical stop records how it ended.
bool run_to_end(RunLoop& loop, const RunRequest& request, Clock::time_point begin,
                const Checkpoint& checkpoint) {
  // summary.json's `resumed`: this invocation started from a checkpoint.
  const bool from_checkpoint = request.resume || !request.branch_from.empty();
  if (from_checkpoint)
    loop.start_from(checkpoint);
  else
    loop.start_fresh();
  auto seconds = [&] {
    return std::chrono::duration<double>(Clock::now() - begin).count();
  };
  try {
    loop.run();
  } catch (const SimulationError& e) {
    loop.write_summary(seconds(), from_checkpoint, e.kind, e.what());
    throw;
  }
  if (loop.paused())
    return false;
  loop.write_summary(seconds(), from_checkpoint);
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
  } else if (!request.branch_from.empty()) {
    checkpoint = read_checkpoint(request.branch_from + "/checkpoint.h5");
    o = branch_options(request.branch_from, checkpoint, request.resume_overrides);
  }
  // Everything the options leave to be settled, settled once; the rest only reads it.
  const RunPlan plan = resolve_run_plan(o, request.quiet);
  if (plan.options.threads > 0)
    omp_set_num_threads(plan.options.threads);
  // Built first: a backend that cannot run the plan stops the run before anything is
  // written.
  RunLoop loop(plan, request.outdir, request.quiet, request.pause_at, request.profile);
  if (request.resume) {
    loop.check_series(checkpoint);
  } else {
    RunFiles::prepare_fresh(request.outdir);
    if (!request.branch_from.empty()) {
      RunFiles::copy_series(request.branch_from, request.outdir);
      loop.check_series(checkpoint);
    }
  }
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
