#pragma once
// The 3-D FFTs of Spectral Ewald on the device: cuFFT plans for the three force
// components of an m0 x m1 x m2 grid at once (batch of 3), real-to-complex forward and
// complex-to-real backward, unnormalised like FFTW. Layouts match spectral_kernels.cu:
// grids component after component (m0 m1 m2 doubles each, row-major), spectra likewise
// (m0 m1 (m2/2 + 1) interleaved complex each).
namespace capsim::cuda {

class DeviceFft3 {
public:
  explicit DeviceFft3(const int m[3]);
  ~DeviceFft3();
  DeviceFft3(const DeviceFft3&) = delete;
  DeviceFft3& operator=(const DeviceFft3&) = delete;

  void forward(double* grid, double* spectrum);
  // Overwrites the spectrum (cuFFT's complex-to-real transforms may use it as scratch).
  void backward(double* spectrum, double* grid);

private:
  int forward_ = 0, backward_ = 0; // cufftHandle
};

} // namespace capsim::cuda
