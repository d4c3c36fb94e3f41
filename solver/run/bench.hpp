#pragma once
// `capsim bench`: the cost and accuracy of one periodic single-layer evaluation (the
// velocity of every node of M capsules in a sheared box) for one method and tolerance, on
// a reproducible suspension configuration, against a tight-tolerance direct Ewald
// reference on the same configuration. Prints one JSON object.
#include <string>

namespace capsim {

struct BenchOptions {
  int capsules = 27;
  int mesh_level = 3;
  double phi = 0.3;
  std::string method = "spectral"; // spectral | direct | patches
  int patch_level = 1;             // patches: faces of this icosphere level (P = 80)
  double tolerance = 1e-4;
  double strain = 0.0;
  int seed = 1;
  double xi = 0;                               // 0: the automatic choice of `capsim run`
  std::string precision = "double";            // spectral grids: double, single or auto
  std::string real_space_precision = "double"; // the real-space sum: the same choices
  int repeats = 3;            // timed evaluations (spectral: after an untimed warm-up)
  std::string reference_file; // cache of the reference velocities ("" = none)
  bool reference = true;      // false: no reference, no rel_error
};

// Runs the benchmark; returns the JSON text. Throws ConfigError on bad options.
std::string run_benchmark(const BenchOptions& o);

} // namespace capsim
