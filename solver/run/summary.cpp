#include "run/summary.hpp"

#include "io/json_writer.hpp"

#include <cstdlib>

namespace capsim {

void write_summary_json(const std::string& path, const RunOptions& o,
                        const RunAverages& a, const SummaryFacts& facts) {
  Rheology r = rheology_from_stresslet(a.stresslet_mean, o.phi, o.ca);
  JsonWriter j;
  j.begin_object();
  j.field("program", "capsim");
  j.field("version", CAPSIM_VERSION);
  // In the dilute limit (phi = 0) mu_sp, N1, N2 are the intrinsic values per unit phi.
  j.field("intrinsic", o.phi == 0);
  // How the run ended: "t_end", or "contact"/"numerical" for a stop whose averages
  // cover [t_avg_start, t_end] up to the last good sample (null when that is empty).
  j.field("ended", facts.ended);
  if (!facts.end_message.empty())
    j.field("end_message", facts.end_message);
  j.field("taylor_D", a.D_mean);
  j.field("taylor_D_std", a.D_std);
  j.field("theta_D_deg", a.theta_D_mean);
  j.field("theta_D_std_deg", a.theta_D_std);
  j.matrix("stresslet", a.stresslet_mean);
  j.field("principal_stresslet_diff", a.principal_diff_mean);
  j.field("theta_S_deg", a.theta_S_mean);
  j.field("mu_sp", r.mu_sp);
  j.field("N1", r.N1);
  j.field("N2", r.N2);
  j.field("energy_mean", a.energy_mean);
  j.field("volume_error_max", a.volume_error_max);
  j.field("volume_drift_max", a.volume_drift_max);
  // The repulsion (suspension.repulsion_force > 0): samples in which it acted, and the
  // most nodes within its range in one sample; both 0 when it is off or never acted.
  j.field("repelled_samples", a.repelled_samples);
  j.field("repelled_nodes_max", a.repelled_nodes_max);
  j.field("t_avg_start", a.t_start);
  j.field("t_end", a.t_end);
  j.field("samples", a.rows);
  j.field("sample_values", a.values);
  j.field("steps", facts.steps);
  j.field("dt", facts.dt);
  j.field("rejected_steps", facts.rejected_steps);
  j.field("mean_edge_length", facts.mean_edge);
  j.field("wall_seconds", facts.wall_seconds);
  j.field("cpu_seconds", facts.cpu_seconds);
  j.field("threads", facts.threads);
  j.field("resumed", facts.resumed);
  if (facts.box_side > 0) {
    j.field("box_side", facts.box_side);
    j.field("ewald_xi", facts.ewald_xi);
    j.field("ewald_r_cut", facts.ewald_r_cut);
    j.field("ewald_k_cut", facts.ewald_k_cut);
    j.field("spectral_grid", facts.spectral_grid);
    j.field("spectral_support", facts.spectral_support);
    if (!facts.spectral_precision.empty())
      j.field("spectral_precision", facts.spectral_precision);
    j.field("real_space_precision", facts.real_space_precision);
  }
  if (o.lambda != 1) { // the second-kind solves (none at lambda = 1)
    const SecondKindStats& k = facts.second_kind;
    j.field("gmres_solves", k.solves);
    j.field("gmres_iterations_mean", k.solves ? double(k.iterations) / k.solves : 0.0);
    j.field("gmres_iterations_max", k.max_iterations);
    j.field("gmres_residual_max", k.max_residual);
  }
  j.begin_object("parameters");
  for (const auto& [key, value] : flat_values(o)) {
    char* end = nullptr;
    double number = std::strtod(value.c_str(), &end);
    if (!value.empty() && *end == '\0')
      j.field(key, number);
    else if (value == "true" || value == "false") // a boolean key
      j.field(key, value == "true");
    else
      j.field(key, value);
  }
  j.end_object();
  j.end_object();
  write_text_atomically(path, j.str());
}

void add_box_facts(const PeriodicBox& box, SummaryFacts& f) {
  f.box_side = box.L;
  f.ewald_xi = box.ewald.xi;
  f.ewald_r_cut = box.ewald.r_cut;
  f.ewald_k_cut = box.ewald.k_cut;
  auto precision = [](bool single) {
    return to_string(single ? Precision::single_precision : Precision::double_precision);
  };
  if (box.method == EwaldMethod::spectral) {
    f.spectral_grid.assign(box.grid.grid, box.grid.grid + 3);
    f.spectral_precision = precision(box.grid.single);
  }
  f.spectral_support = box.grid.support;
  f.real_space_precision = precision(box.ewald.single_real);
}

} // namespace capsim
