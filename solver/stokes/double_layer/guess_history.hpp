#pragma once
// GMRES's first guess for the second-kind solve (second_kind_solve.hpp) at time t, from
// the solutions of the evaluations before it.
//
// Why extrapolate: GMRES stops at a residual relative to the right-hand side, so the
// iterations a solve takes grow with the log of its first guess's error. The previous
// evaluation's velocity is off by O(dt) wherever the evaluation time moves on (a
// Runge-Kutta step's later stages), by O(dt^2) where it does not (a step's first stage
// after the last stage of the step before, which evaluated nearly the same state); the
// line through the latest solutions at the two latest times is off by O(dt^2)
// everywhere (measured: benchmarks/records/viscosity_ratio_cost_dense.json).
#include "common/choice.hpp"
#include "common/vec3.hpp"

#include <vector>

namespace capsim {

enum class GmresGuess {
  previous,    // the latest evaluation's solution
  extrapolated // linear in t through the latest solutions at the two latest times
};
inline constexpr Choice<GmresGuess> kGmresGuesses[] = {
    {"previous", GmresGuess::previous}, {"extrapolated", GmresGuess::extrapolated}};

class GuessHistory {
public:
  explicit GuessHistory(GmresGuess kind = GmresGuess::extrapolated) : kind_(kind) {}

  bool empty() const { return last_.empty(); }
  void clear() {
    last_.clear();
    before_.clear();
  }
  // Keeps the solution u of the evaluation at time t.
  void record(double t, const std::vector<Vec3>& u);
  // The first guess for the evaluation at time t (the history must not be empty).
  std::vector<Vec3> guess(double t) const;

  bool operator==(const GuessHistory& o) const {
    return kind_ == o.kind_ && t_last_ == o.t_last_ && t_before_ == o.t_before_ &&
           last_ == o.last_ && before_ == o.before_;
  }

private:
  GmresGuess kind_;
  double t_last_ = 0, t_before_ = 0;
  std::vector<Vec3> last_;   // the latest solution, at t_last_
  std::vector<Vec3> before_; // extrapolated: the latest one at an earlier t_before_
};

} // namespace capsim
