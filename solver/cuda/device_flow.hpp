#pragma once
// The CUDA backend of CapsuleFlow: the same velocity field (membrane traction, free-space
// or periodic single layer with Spectral Ewald, shear flow) and Heun step, evaluated on
// the device. The mesh, its reference state and every work array stay in device memory
// for the whole run; a step copies only the node positions in and out (the volume
// constraint, checks and diagnostics run on the host). Plain C++: device_flow.cpp
// implements it with CUDA, cuda_unavailable.cpp (builds without CUDA) refuses to.
#include "dynamics/time_stepping.hpp"

#include <memory>
#include <vector>

namespace capsim {

class DeviceFlow {
public:
  // Throws std::invalid_argument for what the device path does not do (the consistent
  // load mapping, direct Ewald sums, r_cut >= L/3), std::runtime_error for CUDA errors.
  DeviceFlow(const Membrane& membrane, int num_capsules, double shear_rate,
             LoadMapping load, const QuadratureOptions& quadrature,
             const PeriodicBox& box);
  ~DeviceFlow();
  DeviceFlow(const DeviceFlow&) = delete;
  DeviceFlow& operator=(const DeviceFlow&) = delete;

  // The nodal traction q (lumped) at positions x.
  void traction(const std::vector<Vec3>& x, std::vector<Vec3>& q);
  // Node velocities at positions x and time t.
  void velocity(const std::vector<Vec3>& x, double t, std::vector<Vec3>& u);
  // One Heun step from time t, both stages on the device.
  void rk2_step(std::vector<Vec3>& x, double t, double dt);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace capsim
