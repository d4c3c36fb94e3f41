#pragma once
// Plain records that the run loop hands to the output files. Units follow
// docs/conventions.md: lengths in a, times in 1/gammadot, stresslets and energies in Gs
// a^2.
#include "common/vec3.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace capsim {

// Diagnostics of one capsule at one sample time.
struct CapsuleSample {
  double taylor_D = 0;       // Taylor parameter D of the x-y section of Mo
  double theta_D_deg = 0;    // angle of the major axis with +x, (-90, 90]
  Mat3 stresslet;            // S = int 1/2 (r q + q r) dA, in Gs a^2
  double principal_diff = 0; // S1 - S2 of the x-y block, in Gs a^2
  double theta_S_deg = 0;    // angle of S1's eigenvector with +x, (-90, 90]
  Vec3 centroid;             // volume centroid
  double energy = 0;         // membrane elastic energy W, in Gs a^2
  double volume_error = 0;   // (V - V0) / V0 of the state (after the volume constraint)
  double volume_drift = 0;   // largest (V - V0) / V0 one step made before the constraint
                             // restored V0, since the previous sample
  double repelled_nodes = 0; // nodes within the repulsion range of another capsule
                             // (0 when the repulsion is off)
  double compressed_elements = 0; // elements whose T2 of eq. 2.10 is compressive
                                  // (membrane/compression.hpp)
  double min_tension = 0;         // the smallest T2 of eq. 2.10 over Gs of any element
};

// One row of the time series: all capsules at one time.
struct Sample {
  double time = 0; // gammadot t
  std::int64_t step = 0;
  std::vector<CapsuleSample> capsules;
};

// Everything needed to continue a run exactly where it stopped.
struct Checkpoint {
  double time = 0;
  std::int64_t step = 0;
  std::int64_t samples_written = 0;   // rows of timeseries.h5 that belong to this state
  std::int64_t snapshots_written = 0; // mesh snapshots written so far
  double next_dt = 0;                 // adaptive step: the step size to try next
  std::int64_t rejected_steps = 0;    // adaptive step: steps rejected so far
  // Adaptive step: sample k falls at sample_origin_time + (k - sample_origin_index) times
  // the sample interval; (0, 0) unless a resume or branch moved the grid (another
  // interval, or a branch from a fixed step, whose samples count steps).
  double sample_origin_time = 0;
  std::int64_t sample_origin_index = 0;
  // Fixed step: step n ends at step_origin_time + (n - step_origin_index) dt; (0, 0)
  // unless a branch took another fixed step (its grid starts where it branched).
  double step_origin_time = 0;
  std::int64_t step_origin_index = 0;
  int num_capsules = 1;
  int nodes_per_capsule = 0;
  std::vector<double> volume0; // reference volume of each capsule
  std::vector<Vec3> positions; // num_capsules * nodes_per_capsule node positions
  std::string options_yaml;    // the resolved run options, for a consistency check
};

} // namespace capsim
