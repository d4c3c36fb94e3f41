#include "dynamics/adaptive_step.hpp"

namespace capsim {
namespace {

// 1e-9: t_end a whole number of steps from the origin up to rounding takes no extra step.
long last_fixed_step(const StepOrigin& o, double t_end, double dt) {
  return o.step + std::lround(std::ceil((t_end - o.time) / dt - 1e-9));
}

} // namespace

TimeStepper::TimeStepper(Stepper& scheme, double tolerance, double dt, double min_dt,
                         double t_end)
    : scheme_(scheme), dt_(dt), min_dt_(min_dt), t_end_(t_end),
      fixed_steps_(last_fixed_step({}, t_end, dt)) {
  control_.tolerance = tolerance;
}

StepOutcome TimeStepper::step_towards(std::vector<Vec3>& x, double target) {
  const double t = time();
  const double h = control_.size(dt_, t, target);
  std::vector<Vec3> trial = x;
  const double error = scheme_.step(trial, t, h);
  const double proposal = control_.next(h, error);
  if (!control_.accept(error)) {
    ++rejected_;
    dt_ = proposal;
    return dt_ < min_dt_ ? StepOutcome::failed : StepOutcome::rejected;
  }
  if (!(h < dt_ && proposal >= h))
    dt_ = proposal;
  x = std::move(trial);
  ++steps_;
  t_ = h == target - t ? target : t + h;
  return StepOutcome::accepted;
}

void TimeStepper::resume(long steps, double t, double next_dt, long rejected,
                         StepOrigin origin) {
  steps_ = steps;
  t_ = t;
  rejected_ = rejected;
  origin_ = origin;
  // A fixed step whose grid misses t (a branch with another step, or from an adaptive
  // one) starts its grid there; on its own grid (a resume, a branch with the same step)
  // it goes on as the unbroken run.
  if (fixed() && time() != t)
    origin_ = {steps, t};
  fixed_steps_ = last_fixed_step(origin_, t_end_, dt_);
  if (!fixed() && next_dt > 0)
    dt_ = next_dt;
}

} // namespace capsim
