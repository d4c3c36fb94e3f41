#pragma once
// Host emulation of the part of the CUDA runtime that capsim uses (CAPSIM_CUDA=EMULATE,
// docs/gpu.md). With this folder on the include path the .cu files and the backend's host
// files compile with the host compiler unchanged: kernels become plain functions, a
// launch (CAPSIM_LAUNCH in launch.cuh) loops over the grid, device memory is host memory
// that this runtime tracks, so that sizes and pointers are checked as a GPU would (or
// would not) accept them.
//
// Not provided on purpose: __shared__ and __syncthreads. A block's threads run one after
// another here, so a barrier cannot be honoured; the kernels need none.
#include <cstddef>

#define __host__
#define __device__
#define __global__

struct uint3 {
  unsigned int x = 0, y = 0, z = 0;
};
struct dim3 {
  unsigned int x = 1, y = 1, z = 1;
  constexpr dim3(unsigned int x_ = 1, unsigned int y_ = 1, unsigned int z_ = 1)
      : x(x_), y(y_), z(z_) {}
};

// Set by the emulated launch for the thread it runs; one copy per OpenMP thread, since
// blocks run in parallel.
inline thread_local uint3 threadIdx, blockIdx;
inline thread_local dim3 blockDim, gridDim;

enum cudaError_t {
  cudaSuccess = 0,
  cudaErrorInvalidValue = 1,
  cudaErrorMemoryAllocation = 2,
  cudaErrorInvalidConfiguration = 9,
  cudaErrorInvalidDevicePointer = 17,
  cudaErrorIllegalAddress = 700,
};

enum cudaMemcpyKind {
  cudaMemcpyHostToHost = 0,
  cudaMemcpyHostToDevice = 1,
  cudaMemcpyDeviceToHost = 2,
  cudaMemcpyDeviceToDevice = 3,
};

struct cudaDeviceProp {
  char name[256] = {};
  size_t totalGlobalMem = 0;
  int major = 0, minor = 0;
};

// Fresh allocations are filled with 0xff bytes (NaN as doubles, -1 as ints), as
// cudaMalloc does not clear memory either: a read before the first write shows up.
cudaError_t cudaMalloc(void** p, size_t bytes);
cudaError_t cudaFree(void* p);
// Both ranges are checked against the allocations the kind implies.
cudaError_t cudaMemcpy(void* dst, const void* src, size_t bytes, cudaMemcpyKind kind);
cudaError_t cudaMemset(void* p, int value, size_t bytes);
cudaError_t cudaGetLastError();
const char* cudaGetErrorString(cudaError_t e);
cudaError_t cudaGetDeviceCount(int* count);
cudaError_t cudaGetDeviceProperties(cudaDeviceProp* p, int device);

// Device-side atomics: blocks run on several OpenMP threads.
inline double atomicAdd(double* address, double value) {
  double old;
#pragma omp atomic capture
  {
    old = *address;
    *address += value;
  }
  return old;
}

namespace capsim_emulation {

// Whether [p, p + bytes) lies inside one live cudaMalloc allocation.
bool is_device_range(const void* p, size_t bytes);
// Records a launch or runtime error for the next cudaGetLastError (per host thread).
void set_last_error(cudaError_t e);

} // namespace capsim_emulation
