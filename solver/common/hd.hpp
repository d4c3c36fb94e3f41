#pragma once
// CAPSIM_HD marks pointwise physics that both the CPU path and CUDA kernels call.
// Under nvcc it expands to __host__ __device__; in a plain C++ build it is empty.
#if defined(__CUDACC__)
#define CAPSIM_HD __host__ __device__ inline
#else
#define CAPSIM_HD inline
#endif
