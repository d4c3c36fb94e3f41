#pragma once
// The flow on the CPU (OpenMP): every option of the solver.
#include "dynamics/flow.hpp"

#include <memory>

namespace capsim {

class CpuFlow : public Flow {
public:
  static FlowCapabilities capabilities() { return {}; } // everything

  explicit CpuFlow(const FlowSetup& setup);

  Backend backend() const override { return Backend::cpu; }
  void traction(const std::vector<Vec3>& x, double t,
                std::vector<Vec3>& q) const override;

protected:
  void evaluate_velocity(const std::vector<Vec3>& x, double t,
                         std::vector<Vec3>& u) const override;

private:
  std::unique_ptr<SpectralEwald> spectral_; // FFT plans and grids, made once
};

} // namespace capsim
