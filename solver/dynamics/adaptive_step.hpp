#pragma once
// The step of the one time loop: a scheme's step (dynamics/time_schemes.hpp) accepted or
// rejected by a controller, the size of the next one, and the rule that gives up.
// The schemes' estimates are the local error of their first-order companions,
// err ~ C dt^2, so the step that would make err = tolerance is dt (tolerance /
// err)^(1/2); a safety factor and bounds on the change keep it from oscillating (Hairer,
// Norsett & Wanner, Solving ODEs I, II.4). A fixed step is the controller that accepts
// every step and keeps dt (as PETSc TS's TSAdaptNONE), so that a run has one loop.
#include "dynamics/time_schemes.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace capsim {

struct StepController {
  double tolerance = 0; // largest step error (dynamics/step_error.hpp), in a; 0: fixed
  double safety = 0.9;  // aim below the tolerance
  double min_factor = 0.2, max_factor = 2.0;

  bool fixed() const { return tolerance <= 0; }

  // A step is accepted when its error is within the tolerance (a NaN never is); a fixed
  // step always.
  bool accept(double error) const { return fixed() || error <= tolerance; }

  // The step to try after a step of size dt with this error (NaN: the smallest factor);
  // a fixed step keeps dt.
  double next(double dt, double error) const {
    if (fixed())
      return dt;
    if (!(error >= 0) || std::isinf(error))
      return min_factor * dt;
    const double factor = error > 0 ? safety * std::sqrt(tolerance / error) : max_factor;
    return dt * std::clamp(factor, min_factor, max_factor);
  }

  // The step from t aimed at target: a fixed step takes its whole dt (its steps stay on
  // the grid n dt and pass over the targets), an adaptive one never passes the target.
  double size(double dt, double t, double target) const {
    return fixed() ? dt : std::min(dt, target - t);
  }
};

// Where a fixed step's grid starts: its n-th step ends at time + (n - step) dt. (0, 0)
// for a run from rest and every resume of it; a branch with another fixed step starts
// its grid at the checkpoint it starts from.
struct StepOrigin {
  long step = 0;
  double time = 0;
};

enum class StepOutcome {
  accepted, // x and t advanced
  rejected, // x and t unchanged; the next try is shorter
  failed    // rejected, and the step fell below its floor: the state is broken
};

// One step after another of a scheme, under its controller, from t = 0 to t_end. Steps
// are aimed at a target time (the next sample); an adaptive step never passes it, and a
// step shortened to land on it does not shrink the step after it unless its own error
// asks for that.
class TimeStepper {
public:
  // tolerance 0: a fixed step dt; else dt is the first step and min_dt the floor below
  // which a rejected step gives up (StepOutcome::failed).
  TimeStepper(Stepper& scheme, double tolerance, double dt, double min_dt, double t_end);

  // Tries one step from (x, time()) of at most dt() towards target.
  StepOutcome step_towards(std::vector<Vec3>& x, double target);

  bool fixed() const { return control_.fixed(); }
  // At t_end: a fixed step after ceil((t_end - origin time) / dt) steps on its grid.
  bool finished() const { return fixed() ? steps_ >= fixed_steps_ : t_ >= t_end_; }
  // gammadot t: origin time + (n - origin step) dt exactly for a fixed step (n dt from
  // rest: 0 + n dt is n dt to the bit), so a resumed run stays on its grid.
  double time() const {
    return fixed() ? origin_.time + double(steps_ - origin_.step) * dt_ : t_;
  }
  // Steps since the fixed step's grid began (all of them from rest).
  long grid_steps() const { return steps_ - origin_.step; }
  const StepOrigin& origin() const { return origin_; }
  double dt() const { return dt_; } // the step to try next (a fixed step: dt)
  double mean_dt() const { return fixed() || steps_ == 0 ? dt_ : t_ / steps_; }
  long steps() const { return steps_; }       // accepted so far
  long rejected() const { return rejected_; } // rejected so far
  // Continues a run from its checkpoint (next_dt <= 0: none saved, keep dt) on the
  // fixed step's grid from `origin`, or from (steps, t) where that grid misses t.
  void resume(long steps, double t, double next_dt, long rejected,
              StepOrigin origin = {});

private:
  Stepper& scheme_;
  StepController control_;
  double dt_, min_dt_, t_end_;
  StepOrigin origin_;
  long fixed_steps_; // of a fixed step: its last, which may pass t_end
  double t_ = 0;     // gammadot t of an adaptive step
  long steps_ = 0, rejected_ = 0;
};

} // namespace capsim
