#include "diagnostics/averages.hpp"

#include "common/suspension.hpp"

#include <cmath>

namespace capsim {
namespace {

// Mean and population standard deviation by Welford's update: the sum / sum-of-squares
// form cancels catastrophically when the spread is small against the mean (theta_D near
// 20 degrees varying by 1e-4, say), this one does not.
struct MeanStd {
  double m = 0, m2 = 0; // running mean, sum of squared deviations from it
  long n = 0;
  void add(double v) {
    ++n;
    const double delta = v - m;
    m += delta / n;
    m2 += delta * (v - m);
  }
  double mean() const { return n ? m : NAN; }
  // No values: NaN like the mean (summary.json null), not a spread of 0 that was never
  // measured.
  double std() const { return n == 0 ? NAN : n < 2 ? 0 : std::sqrt(m2 / n); }
};

} // namespace

RunAverages time_average(const std::vector<Sample>& samples, double t_start,
                         double t_end) {
  RunAverages a;
  a.t_start = t_start;
  a.t_end = t_end;
  MeanStd d, th, ps, ts, en;
  for (const auto& s : samples) {
    double repelled = 0;
    for (const auto& c : s.capsules) {
      a.volume_error_max = std::max(a.volume_error_max, std::abs(c.volume_error));
      a.volume_drift_max = std::max(a.volume_drift_max, std::abs(c.volume_drift));
      repelled += c.repelled_nodes;
    }
    a.repelled_samples += repelled > 0;
    a.repelled_nodes_max = std::max(a.repelled_nodes_max, repelled);
    if (s.time < t_start - 1e-9 || s.time > t_end + 1e-9)
      continue;
    ++a.rows;
    for (const auto& c : s.capsules) {
      d.add(c.taylor_D);
      th.add(c.theta_D_deg);
      ps.add(c.principal_diff);
      ts.add(c.theta_S_deg);
      en.add(c.energy);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          a.stresslet_mean.m[i][j] += c.stresslet.m[i][j];
    }
  }
  a.values = d.n;
  for (auto& row : a.stresslet_mean.m)
    for (double& v : row)
      v = a.values ? v / a.values : NAN;
  a.D_mean = d.mean(), a.D_std = d.std();
  a.theta_D_mean = th.mean(), a.theta_D_std = th.std();
  a.principal_diff_mean = ps.mean(), a.theta_S_mean = ts.mean();
  a.energy_mean = en.mean();
  return a;
}

Rheology rheology_from_stresslet(const Mat3& s, double phi, double ca) {
  const double f = particle_stress_factor(phi, ca);
  return {f * s.m[0][1], f * (s.m[0][0] - s.m[1][1]), f * (s.m[1][1] - s.m[2][2])};
}

} // namespace capsim
