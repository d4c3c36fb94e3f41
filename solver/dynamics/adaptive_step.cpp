#include "dynamics/adaptive_step.hpp"

namespace capsim {

StepOutcome AdaptiveStepper::step_towards(std::vector<Vec3>& x, double& t,
                                          double target) {
  const double h = std::min(dt_, target - t);
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
  t = h == target - t ? target : t + h;
  return StepOutcome::accepted;
}

} // namespace capsim
