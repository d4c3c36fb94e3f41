#include "stokes/double_layer/guess_history.hpp"

#include <cmath>

namespace capsim {
namespace {

// Whether two evaluation times are one: a step's last stage at t + dt and the next
// step's first at the sum of the steps differ in the last bits (a line through both
// would be steeper than any solution: 35 GMRES iterations instead of 6).
bool same_time(double a, double b) {
  return std::abs(a - b) <= 1e-9 * (1 + std::abs(a));
}

} // namespace

void GuessHistory::record(double t, const std::vector<Vec3>& u) {
  if (kind_ == GmresGuess::extrapolated && !last_.empty() && !same_time(t, t_last_)) {
    if (t > t_last_) {
      before_ = std::move(last_);
      t_before_ = t_last_;
    } else {
      before_.clear(); // back in time (a rejected step): no line to follow
    }
  }
  last_ = u;
  t_last_ = t;
}

std::vector<Vec3> GuessHistory::guess(double t) const {
  if (before_.empty() || t <= t_last_ || same_time(t, t_last_))
    return last_;
  const double s = (t - t_last_) / (t_last_ - t_before_);
  std::vector<Vec3> g(last_.size());
  for (size_t i = 0; i < g.size(); ++i)
    g[i] = last_[i] + s * (last_[i] - before_[i]);
  return g;
}

} // namespace capsim
