// The emulated CUDA runtime (cuda_runtime.h here): device memory is host memory whose
// allocations are recorded, so that copies, fills and kernel arguments can be checked
// against them; errors are kept per host thread like the runtime's last error. Each
// allocation ends at an inaccessible page, so that a kernel writing or reading past its
// end stops there (a segmentation fault) instead of corrupting other data.
#include "cuda/emulation/emulated_launch.hpp"

#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>
#include <omp.h>
#include <string>
#include <sys/mman.h>
#include <unistd.h>

namespace capsim_emulation {
namespace {

// cudaMalloc aligns to at least 256 bytes.
constexpr size_t kAlignment = 256;

struct Allocation {
  size_t bytes = 0;        // as asked for
  char* mapping = nullptr; // the pages, the guard page last
  size_t mapped = 0;
};

std::mutex allocations_mutex;
std::map<std::uintptr_t, Allocation> allocations; // by start
thread_local cudaError_t last_error = cudaSuccess;

size_t round_up(size_t n, size_t to) {
  return (n + to - 1) / to * to;
}

// The allocation is placed as late in its pages as the alignment allows.
Allocation map_with_guard(size_t bytes) {
  const size_t page = size_t(sysconf(_SC_PAGESIZE));
  Allocation a;
  a.bytes = bytes;
  a.mapped = round_up(round_up(bytes, kAlignment), page) + page;
  void* m =
      mmap(nullptr, a.mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (m == MAP_FAILED)
    return {};
  a.mapping = static_cast<char*>(m);
  mprotect(a.mapping + a.mapped - page, page, PROT_NONE);
  return a;
}

char* start_of(const Allocation& a) {
  const size_t page = size_t(sysconf(_SC_PAGESIZE));
  return a.mapping + a.mapped - page - round_up(a.bytes, kAlignment);
}

cudaError_t fail(cudaError_t e) {
  set_last_error(e);
  return e;
}

} // namespace

void set_last_error(cudaError_t e) {
  last_error = e;
}

bool is_device_range(const void* p, size_t bytes) {
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  const std::lock_guard<std::mutex> lock(allocations_mutex);
  auto it = allocations.upper_bound(a);
  if (it == allocations.begin())
    return false;
  --it;
  const size_t size = it->second.bytes;
  return a - it->first <= size && bytes <= size - (a - it->first);
}

bool valid_launch(dim3 grid, dim3 block) {
  const unsigned long threads = (unsigned long)block.x * block.y * block.z;
  const bool ok = grid.x >= 1 && grid.x <= 0x7fffffffu && grid.y >= 1 &&
                  grid.y <= 65535 && grid.z >= 1 && grid.z <= 65535 && block.x >= 1 &&
                  block.y >= 1 && block.z >= 1 && block.z <= 64 && threads <= 1024;
  if (!ok)
    set_last_error(cudaErrorInvalidConfiguration);
  return ok;
}

} // namespace capsim_emulation

using capsim_emulation::fail;
using capsim_emulation::is_device_range;

cudaError_t cudaMalloc(void** p, size_t bytes) {
  const capsim_emulation::Allocation a = capsim_emulation::map_with_guard(bytes);
  if (!a.mapping)
    return fail(cudaErrorMemoryAllocation);
  *p = capsim_emulation::start_of(a);
  std::memset(*p, 0xff, bytes);
  const std::lock_guard<std::mutex> lock(capsim_emulation::allocations_mutex);
  capsim_emulation::allocations[reinterpret_cast<std::uintptr_t>(*p)] = a;
  return cudaSuccess;
}

cudaError_t cudaFree(void* p) {
  if (!p)
    return cudaSuccess;
  const std::lock_guard<std::mutex> lock(capsim_emulation::allocations_mutex);
  auto& all = capsim_emulation::allocations;
  const auto it = all.find(reinterpret_cast<std::uintptr_t>(p));
  if (it == all.end())
    return fail(cudaErrorInvalidValue);
  munmap(it->second.mapping, it->second.mapped);
  all.erase(it);
  return cudaSuccess;
}

cudaError_t cudaMemcpy(void* dst, const void* src, size_t bytes, cudaMemcpyKind kind) {
  const bool dst_device =
      kind == cudaMemcpyHostToDevice || kind == cudaMemcpyDeviceToDevice;
  const bool src_device =
      kind == cudaMemcpyDeviceToHost || kind == cudaMemcpyDeviceToDevice;
  if ((dst_device && !is_device_range(dst, bytes)) ||
      (src_device && !is_device_range(src, bytes)))
    return fail(cudaErrorInvalidValue);
  if (bytes > 0)
    std::memmove(dst, src, bytes);
  return cudaSuccess;
}

cudaError_t cudaMemset(void* p, int value, size_t bytes) {
  if (!is_device_range(p, bytes))
    return fail(cudaErrorInvalidValue);
  if (bytes > 0)
    std::memset(p, value, bytes);
  return cudaSuccess;
}

cudaError_t cudaGetLastError() {
  const cudaError_t e = capsim_emulation::last_error;
  capsim_emulation::last_error = cudaSuccess;
  return e;
}

const char* cudaGetErrorString(cudaError_t e) {
  switch (e) {
  case cudaSuccess:
    return "no error";
  case cudaErrorInvalidValue:
    return "invalid argument (emulation: a pointer or size outside the device "
           "allocations)";
  case cudaErrorMemoryAllocation:
    return "out of memory";
  case cudaErrorInvalidConfiguration:
    return "invalid configuration argument";
  case cudaErrorInvalidDevicePointer:
    return "invalid device pointer";
  case cudaErrorIllegalAddress:
    return "an illegal memory access was encountered (emulation: a kernel's pointer "
           "argument lies outside every device allocation)";
  }
  return "unknown error";
}

cudaError_t cudaGetDeviceCount(int* count) {
  *count = 1;
  return cudaSuccess;
}

// Reports the host: its memory, and a name that says what runs the kernels. The compute
// capability is that of the oldest GPU the code supports (double atomicAdd).
cudaError_t cudaGetDeviceProperties(cudaDeviceProp* p, int device) {
  if (device != 0)
    return fail(cudaErrorInvalidValue);
  *p = cudaDeviceProp{};
  const std::string name = "host emulation (kernels as loops on " +
                           std::to_string(omp_get_max_threads()) +
                           " OpenMP threads, cuFFT by FFTW)";
  std::strncpy(p->name, name.c_str(), sizeof p->name - 1);
  p->totalGlobalMem = size_t(sysconf(_SC_PHYS_PAGES)) * size_t(sysconf(_SC_PAGESIZE));
  p->major = 6;
  p->minor = 0;
  return cudaSuccess;
}
