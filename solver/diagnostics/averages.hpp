#pragma once
// Time and ensemble averages over a run (paper eqs. 4.1, A3) and the rheology derived
// from the mean stresslet (eqs. 4.5, 4.9, 4.10). Samples are equally spaced in time, so
// the time integral of eq. A3 is the sample mean.
#include "io/records.hpp"

#include <vector>

namespace capsim {

struct RunAverages {
  double t_start = 0, t_end = 0; // averaging window actually used
  long rows = 0;                 // samples in the window
  long values = 0;               // rows * capsules
  double D_mean = 0, D_std = 0;
  double theta_D_mean = 0, theta_D_std = 0; // degrees
  Mat3 stresslet_mean;                      // Gs a^2
  double principal_diff_mean = 0;           // <S1 - S2>, Gs a^2
  double theta_S_mean = 0;                  // degrees
  // Over the whole run: max |V - V0|/V0 of the states, and of one step's drift before
  // the constraint corrected it.
  double volume_error_max = 0, volume_drift_max = 0;
  // Over all samples: how many had repelled nodes, and the most in one sample.
  long repelled_samples = 0;
  double repelled_nodes_max = 0;
  double energy_mean = 0;
};

// Averages over the samples with t_start <= time <= t_end.
RunAverages time_average(const std::vector<Sample>& samples, double t_start,
                         double t_end);

// mu_sp, N1, N2 (over mu gammadot) from <S> in Gs a^2: factor 3 phi / (4 pi Ca).
// For phi = 0 (dilute limit) phi is left out: the intrinsic values [mu], [N1], [N2].
struct Rheology {
  double mu_sp = 0, N1 = 0, N2 = 0;
};
Rheology rheology_from_stresslet(const Mat3& mean_stresslet, double phi, double ca);

} // namespace capsim
