#pragma once
// `capsim bench`: the cost and accuracy of one periodic single-layer evaluation (the
// velocity of every node of M capsules in a sheared box) for one method and tolerance, on
// a reproducible suspension configuration, against a tight-tolerance direct Ewald
// reference on the same configuration. Prints one JSON object.
#include "stokes/ewald/ewald_setup.hpp"

#include <string>

namespace capsim {

// Spectral at 1e-4, xi automatic, patches of level 1 (P = 80), double precision.
inline EwaldOptions bench_defaults() {
  EwaldOptions e{EwaldMethod::spectral, 1e-4};
  e.precision = e.real_space_precision = Precision::double_precision;
  return e;
}

struct BenchOptions {
  int capsules = 27;
  int mesh_level = 3;
  double phi = 0.3;
  // The periodic sums, the type a run asks with (method, tolerance, xi: 0 = automatic,
  // patch_level, precisions); resolved as a run's on the cpu backend (run/run_plan.hpp).
  EwaldOptions ewald = bench_defaults();
  double strain = 0.0;
  int seed = 1;
  int repeats = 3;            // timed evaluations (spectral: after an untimed warm-up)
  std::string reference_file; // cache of the reference velocities ("" = none)
  bool reference = true;      // false: no reference, no rel_error
};

// Runs the benchmark; returns the JSON text. Throws ConfigError on bad options.
std::string run_benchmark(const BenchOptions& o);

} // namespace capsim
