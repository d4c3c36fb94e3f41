#pragma once
// The step-size controller of an adaptive run. The schemes' embedded estimates are the
// local error of their first-order companions, err ~ C dt^2, so the step that would
// make err = tolerance is dt (tolerance / err)^(1/2); a safety factor and bounds on the
// change keep it from oscillating (Hairer, Norsett & Wanner, Solving ODEs I, II.4).
#include <algorithm>
#include <cmath>

namespace capsim {

struct StepController {
  double tolerance = 0; // largest step error (dynamics/step_error.hpp), in a
  double safety = 0.9;  // aim below the tolerance
  double min_factor = 0.2, max_factor = 2.0;

  // A step is accepted when its error is within the tolerance (a NaN never is).
  bool accept(double error) const { return error <= tolerance; }

  // The step to try after a step of size dt with this error (NaN: the smallest factor).
  double next(double dt, double error) const {
    if (!(error >= 0) || std::isinf(error))
      return min_factor * dt;
    const double factor = error > 0 ? safety * std::sqrt(tolerance / error) : max_factor;
    return dt * std::clamp(factor, min_factor, max_factor);
  }
};

} // namespace capsim
