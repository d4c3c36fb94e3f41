#pragma once
// CAPSIM_HD marks pointwise physics that both the CPU path and CUDA kernels call.
// Under nvcc it expands to __host__ __device__; in a plain C++ build it is empty.
#if defined(__CUDACC__)
#define CAPSIM_HD __host__ __device__ inline
#else
#define CAPSIM_HD inline
#endif

// CAPSIM_HD_INLINE: the same, always inlined. For the pointwise functions called inside
// vectorised loops, which stay scalar if the compiler declines to inline a call.
#if defined(__CUDACC__)
#define CAPSIM_HD_INLINE __host__ __device__ __forceinline__
#elif defined(__GNUC__)
#define CAPSIM_HD_INLINE inline __attribute__((always_inline))
#else
#define CAPSIM_HD_INLINE inline
#endif
