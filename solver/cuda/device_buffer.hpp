#pragma once
// Device memory owned like a std::vector: allocation, size, copies to and from the host.
// Every CUDA error becomes an exception that names the call.
#include <cuda_runtime.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace capsim::cuda {

inline void cuda_check(cudaError_t e, const char* what) {
  if (e != cudaSuccess)
    throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(e));
}

template <class T> class DeviceArray {
public:
  DeviceArray() = default;
  explicit DeviceArray(size_t n) { resize(n); }
  ~DeviceArray() {
    if (p_)
      cudaFree(p_);
  }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;

  // Keeps nothing of the old contents when the size changes.
  void resize(size_t n) {
    if (n == n_)
      return;
    if (p_)
      cudaFree(p_);
    p_ = nullptr;
    n_ = 0;
    if (n > 0)
      cuda_check(cudaMalloc(reinterpret_cast<void**>(&p_), n * sizeof(T)), "cudaMalloc");
    n_ = n;
  }
  void upload(const std::vector<T>& v) {
    resize(v.size());
    cuda_check(cudaMemcpy(p_, v.data(), n_ * sizeof(T), cudaMemcpyHostToDevice),
               "cudaMemcpy to the device");
  }
  // Waits for the kernels before it (the default stream is in order).
  void download(std::vector<T>& v) const {
    v.resize(n_);
    cuda_check(cudaMemcpy(v.data(), p_, n_ * sizeof(T), cudaMemcpyDeviceToHost),
               "cudaMemcpy to the host");
  }
  void zero() { cuda_check(cudaMemset(p_, 0, n_ * sizeof(T)), "cudaMemset"); }
  T* data() { return p_; }
  const T* data() const { return p_; }
  size_t size() const { return n_; }

private:
  T* p_ = nullptr;
  size_t n_ = 0;
};

} // namespace capsim::cuda
