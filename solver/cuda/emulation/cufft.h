#pragma once
// Host emulation of the cuFFT calls capsim makes (device_fft.cpp), carried out by FFTW
// with cuFFT's conventions: unnormalised, forward exponent -1, batches of packed arrays,
// Z2D free to overwrite its input. Buffers must be emulated device memory.
#include <cuda_runtime.h>

typedef int cufftHandle;

enum cufftResult {
  CUFFT_SUCCESS = 0,
  CUFFT_INVALID_PLAN = 1,
  CUFFT_ALLOC_FAILED = 2,
  CUFFT_INVALID_TYPE = 3,
  CUFFT_INVALID_VALUE = 4,
  CUFFT_EXEC_FAILED = 6,
  CUFFT_NOT_SUPPORTED = 16,
};

enum cufftType {
  CUFFT_R2C = 0x2a,
  CUFFT_C2R = 0x2c,
  CUFFT_C2C = 0x29,
  CUFFT_D2Z = 0x6a,
  CUFFT_Z2D = 0x6c,
  CUFFT_Z2Z = 0x69,
};

struct cufftDoubleComplex {
  double x, y;
};

// Only D2Z and Z2D, and only the basic layout (inembed and onembed null): what capsim
// uses. The distances between batches must then be the packed ones.
cufftResult cufftPlanMany(cufftHandle* plan, int rank, int* n, int* inembed, int istride,
                          int idist, int* onembed, int ostride, int odist, cufftType type,
                          int batch);
cufftResult cufftExecD2Z(cufftHandle plan, double* idata, cufftDoubleComplex* odata);
cufftResult cufftExecZ2D(cufftHandle plan, cufftDoubleComplex* idata, double* odata);
cufftResult cufftDestroy(cufftHandle plan);
