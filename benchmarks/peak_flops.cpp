// The machine's double-precision peak as a program can reach it: every thread runs
// independent chains of fused multiply-adds on the widest vectors the CPU has (AVX-512,
// else AVX2, else SSE2, picked at load time like the solver's kernels), enough chains to
// hide the FMA latency. Prints JSON: GFLOP/s per thread count (an FMA counts as 2 flops).
#include "common/vector_clones.hpp"

#include <algorithm>
#include <cstdio>
#include <omp.h>

namespace {

constexpr int kChains = 16;

// Returns a value that depends on every FMA, so that none is optimised away.
CAPSIM_VECTOR_CLONES double fma_chains(long iterations, double seed) {
  double acc[kChains][8];
  for (int c = 0; c < kChains; ++c)
    for (int l = 0; l < 8; ++l)
      acc[c][l] = seed + 1e-3 * (c * 8 + l);
  const double a = 0.999999, b = 1e-7;
  for (long i = 0; i < iterations; ++i)
    for (int c = 0; c < kChains; ++c)
#pragma omp simd
      for (int l = 0; l < 8; ++l)
        acc[c][l] = acc[c][l] * a + b;
  double sum = 0;
  for (int c = 0; c < kChains; ++c)
    for (int l = 0; l < 8; ++l)
      sum += acc[c][l];
  return sum;
}

double measure(int threads, long iterations) {
  double sink = 0;
  const double t0 = omp_get_wtime();
#pragma omp parallel num_threads(threads) reduction(+ : sink)
  sink += fma_chains(iterations, 1.0 + omp_get_thread_num());
  const double seconds = omp_get_wtime() - t0;
  if (sink == 0)
    std::printf("(never)\n");
  return 2.0 * kChains * 8 * double(iterations) * threads / seconds / 1e9;
}

} // namespace

int main() {
  const long iterations = 100000000;
  measure(1, iterations / 10); // warm-up (clock ramps up)
  const int max_threads = omp_get_max_threads();
  std::printf("{\n  \"gflops\": {");
  for (int t = 1; t <= max_threads; ++t) {
    double best = 0;
    for (int r = 0; r < 3; ++r)
      best = std::max(best, measure(t, iterations));
    std::printf("%s\"%d\": %.2f", t > 1 ? ", " : "", t, best);
  }
  std::printf("}\n}\n");
}
