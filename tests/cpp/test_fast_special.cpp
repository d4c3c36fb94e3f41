#include "common/fast_special.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace capsim;

TEST_CASE("exp_nonpositive matches std::exp to 1e-15 relative on [-700, 0]") {
  double worst = 0;
  for (int i = 0; i <= 200000; ++i) {
    const double y = -700.0 * i / 200000.0 - 1e-3 * std::sin(i); // irregular points
    worst = std::max(worst, std::abs(exp_nonpositive(y) / std::exp(y) - 1.0));
  }
  CHECK(worst < 1e-15);
  CHECK(exp_nonpositive(0.0) == 1.0);
}

TEST_CASE("erfcx_nonnegative times exp(-x^2) matches std::erfc to 1e-13 relative") {
  // [0, 6] covers every screened-kernel argument xi r < xi r_cut (4.4 at tolerance 1e-8).
  double worst = 0;
  for (int i = 0; i <= 60000; ++i) {
    const double x = 6.0 * i / 60000.0;
    const double fast = exp_nonpositive(-x * x) * erfcx_nonnegative(x);
    worst = std::max(worst, std::abs(fast / std::erfc(x) - 1.0));
  }
  CHECK(worst < 1e-13);
}
