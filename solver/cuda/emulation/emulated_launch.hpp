#pragma once
// The emulated kernel launch behind CAPSIM_LAUNCH (launch.cuh): the configuration is
// checked as the CUDA runtime checks it, pointer arguments must point into device
// allocations, then every thread of the grid runs the kernel, blocks in parallel on the
// OpenMP threads and the threads of a block one after another.
#include <cuda_runtime.h>
#include <tuple>
#include <type_traits>
#include <utility>

namespace capsim_emulation {

// False (and cudaErrorInvalidConfiguration for cudaGetLastError) for an empty grid or
// block, or one beyond the limits of every current GPU.
bool valid_launch(dim3 grid, dim3 block);

template <class T> bool device_argument(const T&) {
  return true;
}
// A kernel can only dereference device memory: a host pointer would fault on the GPU.
template <class T> bool device_argument(T* p) {
  return p == nullptr || is_device_range(p, 0);
}

template <class F> void run_grid(dim3 grid, dim3 block, const F& thread) {
  const long blocks = long(grid.x) * grid.y * grid.z;
#pragma omp parallel for schedule(dynamic)
  for (long b = 0; b < blocks; ++b) {
    gridDim = grid;
    blockDim = block;
    blockIdx = {unsigned(b % grid.x), unsigned(b / grid.x % grid.y),
                unsigned(b / grid.x / grid.y)};
    for (unsigned z = 0; z < block.z; ++z)
      for (unsigned y = 0; y < block.y; ++y)
        for (unsigned x = 0; x < block.x; ++x) {
          threadIdx = {x, y, z};
          thread();
        }
  }
}

// Launch(kernel, grid, block)(args...) stands for kernel<<<grid, block>>>(args...): the
// arguments are converted to the kernel's parameter types once, as for a launch, and
// each thread gets its own copy of them.
template <class... P> class Launch {
public:
  Launch(void (*kernel)(P...), dim3 grid, dim3 block)
      : kernel_(kernel), grid_(grid), block_(block) {}

  template <class... A> void operator()(A&&... a) const {
    static_assert(sizeof...(A) == sizeof...(P), "wrong number of kernel arguments");
    const std::tuple<std::decay_t<P>...> args(std::forward<A>(a)...);
    if (!valid_launch(grid_, block_))
      return;
    const bool on_device =
        std::apply([](const auto&... p) { return (device_argument(p) && ...); }, args);
    if (!on_device) {
      set_last_error(cudaErrorIllegalAddress);
      return;
    }
    run_grid(grid_, block_, [&] { std::apply(kernel_, args); });
  }

private:
  void (*kernel_)(P...);
  dim3 grid_, block_;
};

} // namespace capsim_emulation
