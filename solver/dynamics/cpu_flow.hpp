#pragma once
// The flow on the CPU (OpenMP): every option of the solver.
#include "dynamics/flow.hpp"

#include <memory>

namespace capsim {

class CpuFlow : public Flow {
public:
  // Everything (FlowCapabilities).
  static FlowCapabilities capabilities() { return {}; }

  explicit CpuFlow(const FlowSetup& setup);

  Backend backend() const override { return Backend::cpu; }
  void traction(const std::vector<Vec3>& x, double t,
                std::vector<Vec3>& q) const override;
  SecondKindStats second_kind_stats() const override { return stats_; }
  void output_velocity(const std::vector<Vec3>& x, double t,
                       std::vector<Vec3>& u) const override;
  void forget_history() const override {
    history_.clear();
    output_.x.clear();
  }

protected:
  void evaluate_velocity(const std::vector<Vec3>& x, double t,
                         std::vector<Vec3>& u) const override;

private:
  void solve_viscosity_ratio(const std::vector<Vec3>& x, double t,
                             std::vector<Vec3>& u) const;
  bool output_velocity_fits(const std::vector<Vec3>& x, double t) const;
  // Keeps the solution u at (x, t) in the history; the first guess at (x, t) from it.
  void remember(const std::vector<Vec3>& x, double t, const std::vector<Vec3>& u) const;
  std::vector<Vec3> first_guess(const std::vector<Vec3>& x, double t) const;

  std::unique_ptr<SpectralEwald> spectral_; // FFT plans and grids, made once
  // lambda != 1: the earlier evaluations' velocities, whence GMRES's first guess for the
  // next one (guess_history.hpp), and the solves' counts. Mutable: evaluating the flow
  // does not change what it is.
  mutable GuessHistory history_;
  mutable SecondKindStats stats_;
  // lambda != 1: the last output's state, guess history and velocity. The next step's
  // first evaluation is usually at that state from that history (a sample comes between
  // two steps), so it takes the output's velocity instead of solving again (the same
  // solve, bit for bit): one solve saved per sample.
  struct OutputVelocity {
    std::vector<Vec3> x;
    GuessHistory history;
    std::vector<Vec3> u;
    double t = 0;
  };
  mutable OutputVelocity output_;
};

} // namespace capsim
