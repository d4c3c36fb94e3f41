#pragma once
// The 3-D FFTs of Spectral Ewald on the device: cuFFT plans for the three force
// components of an m^3 grid at once (batch of 3), real-to-complex forward and
// complex-to-real backward, unnormalised like FFTW. Layouts match spectral_kernels.cu:
// grids component after component (m^3 doubles each, row-major), spectra likewise
// (m^2 (m/2 + 1) interleaved complex each).
namespace capsim::cuda {

class DeviceFft3 {
public:
  explicit DeviceFft3(int m);
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
