#pragma once
// The adaptive step: a scheme's step (dynamics/time_schemes.hpp) accepted or rejected by
// its embedded error estimate, the size of the next one, and the rule that gives up.
// The schemes' estimates are the local error of their first-order companions,
// err ~ C dt^2, so the step that would make err = tolerance is dt (tolerance /
// err)^(1/2); a safety factor and bounds on the change keep it from oscillating (Hairer,
// Norsett & Wanner, Solving ODEs I, II.4).
#include "dynamics/time_schemes.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

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

enum class StepOutcome {
  accepted, // x and t advanced
  rejected, // x and t unchanged; the next try is shorter
  failed    // rejected, and the step fell below its floor: the state is broken
};

// One adaptive step after another of a scheme. Steps are aimed at a target time (the
// next sample) that they never pass; a step shortened to land on the target does not
// shrink the step after it unless its own error asks for that.
class AdaptiveStepper {
public:
  // min_dt: the floor below which a rejected step gives up (StepOutcome::failed).
  AdaptiveStepper(Stepper& scheme, double tolerance, double dt, double min_dt)
      : scheme_(scheme), dt_(dt), min_dt_(min_dt) {
    control_.tolerance = tolerance;
  }

  // Tries one step from (x, t) of at most dt() towards target.
  StepOutcome step_towards(std::vector<Vec3>& x, double& t, double target);

  double dt() const { return dt_; } // the step to try next
  void set_dt(double dt) { dt_ = dt; }
  long rejected() const { return rejected_; } // steps rejected so far
  void set_rejected(long n) { rejected_ = n; }

private:
  Stepper& scheme_;
  StepController control_;
  double dt_, min_dt_;
  long rejected_ = 0;
};

} // namespace capsim
