#pragma once
// The O(N^2)-type inner loops are compiled for several instruction sets and the best one
// the CPU has is picked at load time: a portable build still runs AVX2/AVX-512 code (2x
// faster than baseline SSE2 on the project machine).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__CUDACC__) &&                  \
    !defined(CAPSIM_NO_CLONES)
#define CAPSIM_VECTOR_CLONES                                                             \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define CAPSIM_VECTOR_CLONES
#endif

// CAPSIM_FLATTEN: every call inside the function inlined, lambdas and templates included,
// so that a vector clone's callees are compiled for its instruction set as well: a call
// left out of line runs the callee's baseline (SSE2) build.
#if defined(__GNUC__) && !defined(__CUDACC__)
#define CAPSIM_FLATTEN __attribute__((flatten))
#else
#define CAPSIM_FLATTEN
#endif
