// The outputs of the run loop (run/run_loop.hpp): rows of the time series, checkpoints,
// snapshots and summary.json.
#include "diagnostics/averages.hpp"
#include "diagnostics/capsule_diagnostics.hpp"
#include "diagnostics/snapshot_fields.hpp"
#include "membrane/compression.hpp"
#include "run/run_loop.hpp"
#include "run/summary.hpp"

#include <ctime>
#include <omp.h>

namespace capsim {

// After a step towards `target`, the outputs due. A fixed step counts steps between
// outputs (its steps pass over the sample times), an adaptive one samples (it lands on
// each sample time, the next_sample-th).
void RunLoop::write_outputs(long next_sample, double target) {
  const bool last = clock_.finished();
  const long index = clock_.fixed() ? clock_.grid_steps() : next_sample;
  const bool sample =
      clock_.fixed() ? index % plan_.output.sample_every == 0 || last : time() == target;
  const OutputPlan& every = plan_.output;
  if (sample) {
    ScopeTimer timer(stage(&RunProfile::sampling));
    take_sample();
  }
  if (sample && every.snapshot_every > 0 && index % every.snapshot_every == 0) {
    ScopeTimer timer(stage(&RunProfile::snapshots));
    save_snapshot();
  }
  if ((sample && index % every.checkpoint_every == 0) || last) {
    ScopeTimer timer(stage(&RunProfile::checkpoints));
    save_checkpoint();
  }
  // Only at a regular checkpoint: the unbroken run writes the same one, so a resumed
  // segment continues it to the last bit (a checkpoint forced at `last` would add a row).
  if (!last && pause_at_ > 0 && files_.checkpoint_time() == time() && time() >= pause_at_)
    paused_ = true;
}

void RunLoop::take_sample() {
  std::vector<Vec3> grad;
  std::vector<double> energy = flow_->energy_gradient(x_, grad);
  const int nn = topology().num_nodes;
  Sample s;
  s.time = time();
  s.step = clock_.steps();
  // The stresslet sees the whole load on the membrane, the repulsion's included.
  const std::vector<int> repelled = flow_->add_repulsion(x_, s.time, grad);
  // lambda != 1: the stresslet's velocity term needs u at the sampled state (one more
  // evaluation per sample; none at lambda = 1).
  std::vector<Vec3> u;
  if (o_.lambda != 1)
    flow_->output_velocity(x_, s.time, u);
  for (int c = 0; c < o_.capsules; ++c) {
    s.capsules.push_back(capsule_sample(topology(), &x_[c * nn], &grad[c * nn], energy[c],
                                        v0_[c], o_.ca, u.empty() ? nullptr : &u[c * nn],
                                        o_.lambda));
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
  c.next_dt = clock_.dt();
  c.rejected_steps = clock_.rejected();
  c.sample_origin_time = sample_origin_time_;
  c.sample_origin_index = sample_origin_index_;
  c.step = clock_.steps();
  c.step_origin_index = clock_.origin().step;
  c.step_origin_time = clock_.origin().time;
  c.num_capsules = o_.capsules;
  c.nodes_per_capsule = topology().num_nodes;
  c.volume0 = v0_;
  c.positions = x_;
  c.options_yaml = to_yaml(o_);
  files_.save_checkpoint(c);
  flow_->forget_history(); // the resumed run starts from here as the unbroken one does
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
  flow_->output_velocity(x_, frame.time, frame.velocity);
  flow_->traction(x_, frame.time, frame.traction);
  add_membrane_fields(membrane_, o_.capsules, x_, frame);
  files_.save_snapshot(frame, topology().triangles, x_);
}

void RunLoop::write_summary(double wall_seconds, bool resumed, const std::string& ended,
                            const std::string& end_message) const {
  std::vector<Sample> samples = files_.read_series();
  SummaryFacts facts;
  facts.ended = ended;
  facts.end_message = end_message;
  facts.dt = clock_.mean_dt(); // the mean, if adaptive
  facts.rejected_steps = clock_.rejected();
  facts.mean_edge = plan_.mean_edge;
  facts.steps = clock_.steps();
  facts.wall_seconds = wall_seconds;
  // The cost measure of the accuracy study: CPU time is steadier than wall time on a
  // shared machine, and counts every thread.
  facts.cpu_seconds = static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
  facts.resumed = resumed;
  facts.threads = omp_get_max_threads();
  add_box_facts(box(), facts);
  facts.second_kind = flow_->second_kind_stats();
  double t_final = samples.empty() ? 0.0 : samples.back().time;
  write_summary_json(files_.dir() + "/summary.json", o_,
                     time_average(samples, o_.t_avg_start, t_final), facts);
}

} // namespace capsim
