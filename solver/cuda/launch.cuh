#pragma once
// Launch helpers shared by the .cu files: grid sizes and the error check after a launch.
#include <cuda_runtime.h>
#include <stdexcept>
#include <string>

namespace capsim::cuda {

// 128 threads: enough warps per block to hide latency, small enough that the register-
// heavy quadrature kernels (adaptive subdivision) still fit several blocks per SM.
constexpr int kBlock = 128;

inline int blocks_for(long n) {
  return int((n + kBlock - 1) / kBlock);
}

// Launch errors (bad configuration, no device) surface here as exceptions.
inline void check_launch(const char* kernel) {
  const cudaError_t e = cudaGetLastError();
  if (e != cudaSuccess)
    throw std::runtime_error(std::string("CUDA kernel ") + kernel + ": " +
                             cudaGetErrorString(e));
}

} // namespace capsim::cuda
