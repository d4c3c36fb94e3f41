// cuFFT by FFTW for the emulated device (cufft.h here).
#include <cufft.h>
#include <fftw3.h>
#include <map>
#include <mutex>

namespace {

struct Plan {
  fftw_plan plan = nullptr;
  cufftType type = CUFFT_D2Z;
  size_t real = 0, complex = 0; // per batch, in doubles and complex numbers
  int batch = 0;
};

// The FFTW planner is not thread-safe; the table is shared.
std::mutex plans_mutex;
std::map<cufftHandle, Plan> plans;
cufftHandle next_handle = 1;

fftw_plan make_fftw_plan(int rank, const int* n, cufftType type, int batch, size_t real,
                         size_t complex) {
  // Scratch arrays only for planning: FFTW_ESTIMATE neither reads nor writes them, and
  // FFTW_UNALIGNED lets the plan run on any pair of arrays afterwards.
  double* r = fftw_alloc_real(real * batch);
  fftw_complex* c = fftw_alloc_complex(complex * batch);
  const unsigned flags = FFTW_ESTIMATE | FFTW_UNALIGNED;
  const int rd = int(real), cd = int(complex);
  fftw_plan p = type == CUFFT_D2Z ? fftw_plan_many_dft_r2c(rank, n, batch, r, nullptr, 1,
                                                           rd, c, nullptr, 1, cd, flags)
                                  : fftw_plan_many_dft_c2r(rank, n, batch, c, nullptr, 1,
                                                           cd, r, nullptr, 1, rd, flags);
  fftw_free(r);
  fftw_free(c);
  return p;
}

const Plan* find(cufftHandle h, cufftType type) {
  const std::lock_guard<std::mutex> lock(plans_mutex);
  const auto it = plans.find(h);
  return it == plans.end() || it->second.type != type ? nullptr : &it->second;
}

} // namespace

cufftResult cufftPlanMany(cufftHandle* plan, int rank, int* n, int* inembed, int,
                          int idist, int* onembed, int, int odist, cufftType type,
                          int batch) {
  if (type != CUFFT_D2Z && type != CUFFT_Z2D)
    return CUFFT_NOT_SUPPORTED;
  if (inembed || onembed)
    return CUFFT_NOT_SUPPORTED;
  if (rank < 1 || rank > 3 || batch < 1)
    return CUFFT_INVALID_VALUE;
  Plan p;
  p.type = type;
  p.batch = batch;
  p.real = p.complex = 1;
  for (int d = 0; d < rank; ++d) {
    if (n[d] < 1)
      return CUFFT_INVALID_VALUE;
    p.real *= size_t(n[d]);
    p.complex *= size_t(d + 1 < rank ? n[d] : n[d] / 2 + 1);
  }
  // In the basic layout batches are packed; other distances would be ignored by cuFFT
  // (or not: the documentation leaves it open), so they are refused here.
  const size_t in = type == CUFFT_D2Z ? p.real : p.complex;
  const size_t out = type == CUFFT_D2Z ? p.complex : p.real;
  if (size_t(idist) != in || size_t(odist) != out)
    return CUFFT_INVALID_VALUE;
  const std::lock_guard<std::mutex> lock(plans_mutex);
  p.plan = make_fftw_plan(rank, n, type, batch, p.real, p.complex);
  if (!p.plan)
    return CUFFT_ALLOC_FAILED;
  *plan = next_handle++;
  plans[*plan] = p;
  return CUFFT_SUCCESS;
}

cufftResult cufftExecD2Z(cufftHandle plan, double* idata, cufftDoubleComplex* odata) {
  const Plan* p = find(plan, CUFFT_D2Z);
  if (!p)
    return CUFFT_INVALID_PLAN;
  if (!capsim_emulation::is_device_range(idata, p->batch * p->real * sizeof(double)) ||
      !capsim_emulation::is_device_range(odata,
                                         p->batch * p->complex * 2 * sizeof(double)))
    return CUFFT_INVALID_VALUE;
  fftw_execute_dft_r2c(p->plan, idata, reinterpret_cast<fftw_complex*>(odata));
  return CUFFT_SUCCESS;
}

cufftResult cufftExecZ2D(cufftHandle plan, cufftDoubleComplex* idata, double* odata) {
  const Plan* p = find(plan, CUFFT_Z2D);
  if (!p)
    return CUFFT_INVALID_PLAN;
  if (!capsim_emulation::is_device_range(idata,
                                         p->batch * p->complex * 2 * sizeof(double)) ||
      !capsim_emulation::is_device_range(odata, p->batch * p->real * sizeof(double)))
    return CUFFT_INVALID_VALUE;
  fftw_execute_dft_c2r(p->plan, reinterpret_cast<fftw_complex*>(idata), odata);
  return CUFFT_SUCCESS;
}

cufftResult cufftDestroy(cufftHandle plan) {
  const std::lock_guard<std::mutex> lock(plans_mutex);
  const auto it = plans.find(plan);
  if (it == plans.end())
    return CUFFT_INVALID_PLAN;
  fftw_destroy_plan(it->second.plan);
  plans.erase(it);
  return CUFFT_SUCCESS;
}
