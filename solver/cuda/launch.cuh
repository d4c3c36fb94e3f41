#pragma once
// Launch helpers shared by the .cu files: the launch itself, grid sizes and the error
// check after a launch.
#include <cuda_runtime.h>
#include <stdexcept>
#include <string>

// CAPSIM_LAUNCH(kernel, blocks, threads)(args...) is kernel<<<blocks, threads>>>(args...)
// under nvcc; in the host emulation (CAPSIM_CUDA=EMULATE), which a host compiler builds,
// it runs every thread of the grid on the CPU.
#if defined(CAPSIM_CUDA_EMULATED)
#include "cuda/emulation/emulated_launch.hpp"
#define CAPSIM_LAUNCH(kernel, blocks, threads)                                           \
  ::capsim_emulation::Launch(kernel, blocks, threads)
#else
#define CAPSIM_LAUNCH(kernel, blocks, threads) kernel<<<blocks, threads>>>
#endif

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
