// The CUDA backend in a build without CUDA: it reports that it is missing, and cannot be
// constructed. Configuring with -DCAPSIM_CUDA=ON (or AUTO where nvcc is found) builds
// device_query.cpp and device_flow.cpp instead.
#include "cuda/device_flow.hpp"
#include "cuda/device_query.hpp"

#include <stdexcept>

namespace capsim {

namespace {
const char* const kNotCompiled =
    "this capsim was built without the CUDA backend (configure with -DCAPSIM_CUDA=ON "
    "where the CUDA toolkit is installed)";
} // namespace

bool cuda_backend_compiled() {
  return false;
}

std::string cuda_unavailable_reason() {
  return kNotCompiled;
}

std::string cuda_device_description() {
  return "";
}

struct DeviceFlow::Impl {};

DeviceFlow::DeviceFlow(const FlowSetup& setup) : Flow(setup) {
  throw std::runtime_error(kNotCompiled);
}

DeviceFlow::~DeviceFlow() = default;

void DeviceFlow::traction(const std::vector<Vec3>&, double, std::vector<Vec3>&) const {}
void DeviceFlow::evaluate_velocity(const std::vector<Vec3>&, double,
                                   std::vector<Vec3>&) const {}

} // namespace capsim
