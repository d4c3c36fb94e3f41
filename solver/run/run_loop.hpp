#pragma once
// The time loop of a run and what it writes: built from a resolved run plan
// (run/run_plan.hpp), which it only reads. One loop for every step: a fixed step is the
// controller that accepts every step (dynamics/adaptive_step.hpp). Stepping and the
// checks after a step are in run_loop.cpp, the outputs (samples, checkpoints, snapshots,
// summary.json) in run_outputs.cpp.
#include "dynamics/adaptive_step.hpp"
#include "io/checkpoint_file.hpp"
#include "run/progress.hpp"
#include "run/run_files.hpp"
#include "run/run_plan.hpp"
#include "run/run_profile.hpp"

#include <memory>
#include <string>
#include <vector>

namespace capsim {

class RunLoop {
public:
  // The plan must outlive the loop. Builds the flow on the plan's backend: a backend that
  // cannot run the plan stops here (ConfigError), before anything is written.
  RunLoop(const RunPlan& plan, std::string dir, bool quiet, double pause_at,
          RunProfile* profile);

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
  void step_until_end();
  bool try_step(double target);
  void finish_step();
  void keep_in_box();
  void write_outputs(long next_sample, double target);
  void take_sample();
  void save_checkpoint();
  void save_snapshot();
  void report_progress(bool force);
  double time() const { return clock_.time(); }
  // Adaptive step: the time of the k-th sample (Checkpoint::sample_origin_time).
  double sample_time(long k) const {
    return sample_origin_time_ +
           double(k - sample_origin_index_) * o_.output.sample_interval;
  }
  const Topology& topology() const { return plan_.mesh.topology; }
  const PeriodicBox& box() const { return plan_.box; }
  // The profile's accumulator of one stage, or null without a profile (ScopeTimer).
  double* stage(double RunProfile::*field) const {
    return profile_ ? &(profile_->*field) : nullptr;
  }

  const RunPlan& plan_;
  const RunOptions& o_; // plan_.options
  RunFiles files_;
  ProgressReport progress_;
  double pause_at_;     // RunRequest::pause_at
  bool paused_ = false; // stopped at pause_at_, after a regular checkpoint
  RunProfile* profile_; // RunRequest::profile (null: none)
  Membrane membrane_;
  std::unique_ptr<Flow> flow_;
  std::unique_ptr<Stepper> scheme_;
  TimeStepper clock_;
  std::vector<Vec3> x_;
  std::vector<double> v0_, drift_;
  double sample_origin_time_ = 0; // sample_time()
  long sample_origin_index_ = 0;
};

} // namespace capsim
