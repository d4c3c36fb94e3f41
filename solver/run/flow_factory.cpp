#include "run/flow_factory.hpp"

#include "config/run_options.hpp"
#include "cuda/device_flow.hpp"
#include "cuda/device_query.hpp"
#include "dynamics/cpu_flow.hpp"

#include <sstream>

namespace capsim {

std::string unsupported_by(const FlowSetup& s, const FlowCapabilities& caps,
                           Backend backend) {
  std::ostringstream m;
  const std::string with = " with backend: " + to_string(backend);
  const Membrane& membrane = s.membrane;
  if (s.load != LoadMapping::lumped && !caps.consistent_load)
    m << "membrane.load: must be lumped" << with << ", got '" << to_string(s.load) << "'";
  else if (membrane.bending_modulus() > 0 && !caps.bending)
    m << "membrane.bending: must be 0" << with << " (this backend has no bending), got "
      << membrane.bending_modulus() / membrane.shear_modulus();
  else if (membrane.law() == MembraneLaw::drop && !caps.drop)
    m << "membrane.law: must be neo_hookean" << with
      << " (its membrane kernels have no surface tension; use backend: cpu), got drop";
  else if (s.repulsion.on() && !caps.repulsion)
    m << "suspension.repulsion_force: must be 0" << with
      << " (this backend has no repulsion), got " << s.repulsion.force;
  else if (s.box.L > 0 && s.box.method != EwaldMethod::spectral && !caps.direct_sums)
    m << "method: must be spectral" << with << ", got '" << to_string(s.box.method)
      << "'";
  else if (s.box.L > 0 && s.box.ewald.r_cut >= caps.max_cut_fraction * s.box.L)
    m << "ewald.xi: the real-space cut-off " << s.box.ewald.r_cut << " must stay below "
      << caps.max_cut_fraction << " L = " << caps.max_cut_fraction * s.box.L << with
      << ": raise ewald.xi";
  else if (s.box.L > 0 && s.box.method == EwaldMethod::spectral &&
           s.box.grid.support > caps.max_spread_support)
    m << "ewald.tolerance: the Spectral-Ewald support of " << s.box.grid.support
      << " points exceeds " << caps.max_spread_support << with
      << ": raise ewald.tolerance";
  else if (s.box.L > 0 && s.box.method == EwaldMethod::spectral && s.box.grid.single &&
           !caps.single_grids)
    m << "ewald.precision: must be double" << with
      << " (its grids and FFTs are double precision), got single (set, or auto at "
         "ewald.tolerance >= 1e-5)";
  else if (s.box.L > 0 && s.box.ewald.single_real && !caps.single_real_space)
    m << "ewald.real_space_precision: must be double" << with
      << " (its real-space sum is double precision), got single (set, or auto at "
         "ewald.tolerance >= 1e-5)";
  else if (s.lambda != 1 && !caps.viscosity_ratio)
    m << "lambda: must be 1" << with
      << " (its flow has no double layer; use backend: cpu), got " << s.lambda;
  else if (s.lambda != 1 && s.box.L > 0 && !caps.periodic_viscosity_ratio)
    m << "lambda: must be 1 when phi > 0" << with
      << " (it has no periodic double layer), got " << s.lambda;
  return m.str();
}

FlowCapabilities capabilities_of(Backend backend) {
  return backend == Backend::cuda ? DeviceFlow::capabilities() : CpuFlow::capabilities();
}

void check_flow_supported(Backend backend, const FlowSetup& setup) {
  if (backend == Backend::cuda) {
    const std::string reason = cuda_unavailable_reason();
    if (!reason.empty())
      throw ConfigError("backend: cuda is not available here: " + reason +
                        "; use backend: cpu");
  }
  const std::string why = unsupported_by(setup, capabilities_of(backend), backend);
  if (!why.empty())
    throw ConfigError(why);
}

std::unique_ptr<Flow> make_flow(Backend backend, const FlowSetup& setup) {
  check_flow_supported(backend, setup);
  if (backend == Backend::cuda)
    return std::make_unique<DeviceFlow>(setup);
  return std::make_unique<CpuFlow>(setup);
}

} // namespace capsim
