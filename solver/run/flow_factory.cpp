#include "run/flow_factory.hpp"

#include "config/run_options.hpp"
#include "cuda/device_flow.hpp"
#include "cuda/device_query.hpp"
#include "dynamics/cpu_flow.hpp"

namespace capsim {

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
