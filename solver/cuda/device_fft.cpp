#include "cuda/device_fft.hpp"

#include <cufft.h>
#include <stdexcept>
#include <string>

namespace capsim::cuda {
namespace {

void cufft_check(cufftResult r, const char* what) {
  if (r != CUFFT_SUCCESS)
    throw std::runtime_error(std::string(what) + " failed (cufftResult " +
                             std::to_string(int(r)) + ")");
}

// Packed batches: the basic layout (no embedding) places component a at a * m0 m1 m2 in
// the real array and at a * m0 m1 (m2/2 + 1) in the complex one.
cufftHandle plan3(const int m[3], cufftType type) {
  cufftHandle h = 0;
  int n[3] = {m[0], m[1], m[2]};
  const int real = m[0] * m[1] * m[2], complex = m[0] * m[1] * (m[2] / 2 + 1);
  const bool r2c = type == CUFFT_D2Z;
  cufft_check(cufftPlanMany(&h, 3, n, nullptr, 1, r2c ? real : complex, nullptr, 1,
                            r2c ? complex : real, type, 3),
              "cufftPlanMany");
  return h;
}

} // namespace

DeviceFft3::DeviceFft3(const int m[3]) : forward_(plan3(m, CUFFT_D2Z)) {
  try {
    backward_ = plan3(m, CUFFT_Z2D);
  } catch (...) {
    cufftDestroy(forward_);
    throw;
  }
}

DeviceFft3::~DeviceFft3() {
  cufftDestroy(forward_);
  cufftDestroy(backward_);
}

void DeviceFft3::forward(double* grid, double* spectrum) {
  cufft_check(
      cufftExecD2Z(forward_, grid, reinterpret_cast<cufftDoubleComplex*>(spectrum)),
      "cufftExecD2Z");
}

void DeviceFft3::backward(double* spectrum, double* grid) {
  cufft_check(
      cufftExecZ2D(backward_, reinterpret_cast<cufftDoubleComplex*>(spectrum), grid),
      "cufftExecZ2D");
}

} // namespace capsim::cuda
