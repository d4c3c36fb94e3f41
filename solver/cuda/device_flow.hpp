#pragma once
// The CUDA backend of the flow interface: the same velocity field (membrane traction,
// free-space or periodic single layer with Spectral Ewald, shear flow) and Heun step,
// evaluated on the device. The mesh, its reference state and every work array stay in
// device memory for the whole run; a step copies only the node positions in and out
// (the volume constraint, checks and diagnostics run on the host). Plain C++:
// device_flow.cpp implements it with CUDA, cuda_unavailable.cpp (builds without CUDA)
// refuses to.
#include "dynamics/flow.hpp"
#include "stokes/ewald/spectral_weights.hpp"

#include <memory>
#include <vector>

namespace capsim {

class DeviceFlow : public Flow {
public:
  // The lumped load only (the consistent mass-matrix solve has no device version yet),
  // Spectral Ewald only, no drop; the repulsion's gradient from the host;
  // r_cut < L/3, so that the nearest image of a source is the only one within r_cut (the
  // shortest lattice vector of the sheared box is L, and fractional wrapping finds that
  // image); the spreading stencil within the kernels' fixed bound.
  static FlowCapabilities capabilities() {
    FlowCapabilities c;
    c.consistent_load = c.drop = c.direct_sums = c.single_grids = c.single_real_space =
        c.viscosity_ratio = c.periodic_viscosity_ratio = false;
    c.max_cut_fraction = 1.0 / 3.0;
    c.max_spread_support = kMaxSpreadSupport;
    return c;
  }

  // Throws std::runtime_error for CUDA errors. The factory has checked capabilities().
  explicit DeviceFlow(const FlowSetup& setup);
  ~DeviceFlow() override;

  Backend backend() const override { return Backend::cuda; }
  // The nodal traction q (lumped) at positions x.
  void traction(const std::vector<Vec3>& x, double t,
                std::vector<Vec3>& q) const override;

protected:
  void evaluate_velocity(const std::vector<Vec3>& x, double t,
                         std::vector<Vec3>& u) const override;

private:
  const Vec3* repulsion_gradient(const std::vector<Vec3>& x, double t) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace capsim
