#pragma once
// summary.json: the run's time averages, rheology and facts (docs/usage.md).
#include "config/run_options.hpp"
#include "diagnostics/averages.hpp"
#include "dynamics/flow.hpp"

#include <string>
#include <vector>

namespace capsim {

struct SummaryFacts {
  double dt = 0, mean_edge = 0, wall_seconds = 0;
  double cpu_seconds = 0; // of the process, all threads: this invocation
  long steps = 0;
  long rejected_steps = 0; // adaptive step: tried and rejected
  int threads = 1;
  bool resumed = false;
  double box_side = 0; // periodic box side L; 0 in the dilute limit
  double ewald_xi = 0, ewald_r_cut = 0, ewald_k_cut = 0;
  std::vector<double> spectral_grid; // M_x, M_y, M_z; empty for the direct method
  int spectral_support = 0;          // 0 for the direct method
  std::string spectral_precision;    // "single" or "double"; empty for the direct method
  std::string real_space_precision;  // "single" or "double" (ewald.*precision resolved)
  // lambda != 1: the second-kind solves of this invocation (dynamics/flow.hpp).
  SecondKindStats second_kind;
  std::string ended = "t_end"; // or the SimulationError kind: "contact", "numerical"
  std::string end_message;     // why it stopped early; empty for "t_end"
};

// The box's facts (side, Ewald parameters, grid, precisions as resolved) into f.
void add_box_facts(const PeriodicBox& box, SummaryFacts& f);

void write_summary_json(const std::string& path, const RunOptions& o,
                        const RunAverages& a, const SummaryFacts& facts);

} // namespace capsim
