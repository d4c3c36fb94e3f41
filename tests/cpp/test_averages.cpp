// The time and ensemble averages of diagnostics/averages.hpp.
#include "diagnostics/averages.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace capsim;

namespace {

// Samples at t = 0, 1, ..., n - 1 of one capsule whose D is offset + spread * (-1)^k.
std::vector<Sample> alternating_samples(int n, double offset, double spread) {
  std::vector<Sample> samples(n);
  for (int k = 0; k < n; ++k) {
    samples[k].time = k;
    samples[k].capsules.resize(1);
    samples[k].capsules[0].taylor_D = offset + (k % 2 ? -spread : spread);
    samples[k].capsules[0].theta_D_deg = 20.0 + 1e-3 * k;
  }
  return samples;
}

} // namespace

TEST_CASE("time averages: mean and standard deviation of values with a large common "
          "offset keep their digits",
          "[averages]") {
  // Population std of +-spread is spread exactly. The sum / sum-of-squares form loses
  // it entirely here (sum2/n - mean^2 = 1e8 - 1e8 in doubles of 16 digits); Welford keeps
  // it to rounding.
  const RunAverages a = time_average(alternating_samples(1000, 1e4, 1e-5), 0, 999);
  CHECK(a.values == 1000);
  CHECK(a.D_mean == Approx(1e4).epsilon(1e-15));
  CHECK(a.D_std == Approx(1e-5).epsilon(1e-6));
  // theta_D = 20 + 1e-3 k for k = 0..999: mean 20.4995, std 1e-3 sqrt((n^2 - 1) / 12).
  CHECK(a.theta_D_mean == Approx(20.4995).epsilon(1e-13));
  CHECK(a.theta_D_std ==
        Approx(1e-3 * std::sqrt((1000.0 * 1000.0 - 1) / 12)).epsilon(1e-9));
}

TEST_CASE("time averages: the window selects samples, one value has no spread",
          "[averages]") {
  const RunAverages a = time_average(alternating_samples(10, 0.3, 0.1), 4, 4);
  CHECK(a.rows == 1);
  CHECK(a.D_mean == Approx(0.4));
  CHECK(a.D_std == 0);
  // An empty window (a run stopped before t_avg_start): no mean and no spread.
  const RunAverages none = time_average(alternating_samples(10, 0.3, 0.1), 50, 60);
  CHECK(none.rows == 0);
  CHECK(std::isnan(none.D_mean));
  CHECK(std::isnan(none.D_std));
  CHECK(std::isnan(none.theta_D_std));
}
