// The achieved flop rate of the near-field (real-space) kernel: every thread sums the
// screened Stokeslet over its own buffer of 1024 separations inside r_cut (as the
// real-space sum does per target, with the data in L1/L2), repeatedly. Prints JSON with
// GFLOP/s per thread count, counting kScreenedPairFlops per term; compare with
// peak_flops.
#include "stokes/ewald/real_space_sum.hpp"

#include <algorithm>
#include <cstdio>
#include <omp.h>
#include <random>
#include <vector>

namespace {

double measure(int threads, int repeats) {
  const size_t n = 1024;
  const double xi = 4.0, r_cut = 0.9;
  double sink = 0;
  double seconds = 0;
#pragma omp parallel num_threads(threads) reduction(+ : sink) reduction(max : seconds)
  {
    std::mt19937 rng(17 + omp_get_thread_num());
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> r[3], f[3];
    for (auto& v : r)
      v.reserve(n);
    while (r[0].size() < n) {
      const double x = u(rng) * r_cut, y = u(rng) * r_cut, z = u(rng) * r_cut;
      if (x * x + y * y + z * z < r_cut * r_cut && x * x + y * y + z * z > 1e-6)
        r[0].push_back(x), r[1].push_back(y), r[2].push_back(z);
    }
    for (auto& v : f)
      for (size_t j = 0; j < n; ++j)
        v.push_back(u(rng));
#pragma omp barrier
    const double t0 = omp_get_wtime();
    for (int k = 0; k < repeats; ++k) {
      const capsim::Vec3 s =
          capsim::screened_sum(n, r[0].data(), r[1].data(), r[2].data(), f[0].data(),
                               f[1].data(), f[2].data(), xi + 1e-9 * k);
      sink += s.x + s.y + s.z;
    }
    seconds = omp_get_wtime() - t0;
  }
  if (sink == 0)
    std::printf("(never)\n");
  return capsim::kScreenedPairFlops * double(n) * repeats * threads / seconds / 1e9;
}

} // namespace

int main() {
  const int repeats = 20000;
  measure(1, repeats / 10); // warm-up
  std::printf("{\n  \"flops_per_pair\": %.0f,\n  \"gflops\": {",
              capsim::kScreenedPairFlops);
  for (int t = 1; t <= omp_get_max_threads(); ++t) {
    double best = 0;
    for (int k = 0; k < 3; ++k)
      best = std::max(best, measure(t, repeats));
    std::printf("%s\"%d\": %.2f", t > 1 ? ", " : "", t, best);
  }
  std::printf("}\n}\n");
}
