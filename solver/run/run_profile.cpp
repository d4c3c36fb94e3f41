#include "run/run_profile.hpp"

#include "io/json_writer.hpp"

#include <utility>
#include <vector>

namespace capsim {

void write_run_profile(const std::string& path, const RunProfile& p) {
  const FlowProfile& f = p.flow;
  const PeriodicTimings& e = f.periodic;
  const std::vector<std::pair<const char*, double>> stages = {
      {"membrane_load", f.traction},
      {"unbounded_single_layer", f.unbounded},
      {"ewald_setup", e.setup},
      {"near_corrections", e.near},
      {"real_space", e.real_space},
      {"reciprocal", e.reciprocal},
      {"spreading", e.spectral.spread},
      {"fft", e.spectral.fft},
      {"gathering", e.spectral.gather},
      {"double_layer_setup", f.double_layer_setup},
      {"double_layer_apply", f.double_layer_apply},
      {"volume_rate", f.volume_rate},
      {"evaluations", f.velocity + f.volume_rate},
      {"stepping", p.stepping},
      {"volume_constraint", p.volume_constraint},
      {"state_checks", p.state_checks},
      {"box_and_contact", p.box_and_contact},
      {"sampling", p.sampling},
      {"snapshots", p.snapshots},
      {"checkpoints", p.checkpoints},
      {"loop", p.loop}};
  const double steps = p.steps > 0 ? double(p.steps) : 1.0;
  JsonWriter j;
  j.begin_object();
  j.field("steps", p.steps);
  j.field("evaluations", f.evaluations);
  j.field("real_space_pairs_per_evaluation",
          f.evaluations > 0 ? double(e.real_space_pairs) / double(f.evaluations) : 0.0);
  j.begin_object("seconds_per_step");
  for (const auto& [name, seconds] : stages)
    j.field(name, seconds / steps);
  j.end_object();
  j.begin_object("seconds");
  for (const auto& [name, seconds] : stages)
    j.field(name, seconds);
  j.end_object();
  j.end_object();
  write_text_atomically(path, j.str());
}

} // namespace capsim
