#include "cuda/device_query.hpp"

#include <cuda_runtime.h>
#include <sstream>

namespace capsim {

bool cuda_backend_compiled() {
  return true;
}

std::string cuda_unavailable_reason() {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess)
    return std::string("no usable CUDA device (cudaGetDeviceCount: ") +
           cudaGetErrorString(e) + ")";
  if (count == 0)
    return "no CUDA device found";
  cudaDeviceProp p{};
  if (cudaGetDeviceProperties(&p, 0) != cudaSuccess)
    return "CUDA device 0 cannot be queried";
  // Double-precision atomicAdd (spreading) needs compute capability 6.0.
  if (p.major < 6)
    return std::string("CUDA device 0 (") + p.name +
           ") is older than compute capability 6.0";
  return "";
}

std::string cuda_device_description() {
  cudaDeviceProp p{};
  if (cudaGetDeviceProperties(&p, 0) != cudaSuccess)
    return "";
  std::ostringstream s;
  s << p.name << ", compute capability " << p.major << "." << p.minor << ", "
    << (p.totalGlobalMem >> 20) << " MiB";
  return s.str();
}

} // namespace capsim
