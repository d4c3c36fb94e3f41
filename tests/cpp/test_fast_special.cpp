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

// The single-precision versions (the real-space kernel of ewald.real_space_precision
// single): exp within a few float roundings (6e-8; measured 1.9e-7), erfcx within its
// expansion's 1.3e-7 plus the roundings of 16 Horner steps in float (measured 4.1e-7).
TEST_CASE("exp_nonpositive and erfcx_nonnegative in single precision match to 5e-7") {
  double worst_exp = 0, worst_erfcx = 0;
  for (int i = 0; i <= 60000; ++i) {
    const float y = -87.0f * float(i) / 60000.0f;
    worst_exp =
        std::max(worst_exp, std::abs(exp_nonpositive(y) / std::exp(double(y)) - 1));
    const float x = 6.0f * float(i) / 60000.0f;
    const float fast = erfcx_nonnegative(x, 1.0f / (kErfcxKSingle + x));
    worst_erfcx =
        std::max(worst_erfcx, std::abs(fast / erfcx_nonnegative(double(x)) - 1));
  }
  INFO("exp " << worst_exp << ", erfcx " << worst_erfcx);
  CHECK(worst_exp < 3e-7);
  CHECK(worst_erfcx < 5e-7);
  CHECK(exp_nonpositive(0.0f) == 1.0f);
}
