#pragma once
// Real-space part of the Ewald sum (paper eqs. 2.4, 2.6): at every target x,
//   sum over all images of all far-rule points y with |x - y| < r_cut of J^EI(x - y) f.
// Per target the neighbours are gathered from cell lists into a contiguous buffer, then
// summed in one vectorised loop (the kernel has no branches; see fast_special.hpp).
#include "stokes/cells/periodic_cells.hpp"
#include "stokes/kernels/periodic_stokeslet.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <vector>

namespace capsim {

// sum_j J^EI(r_j) f_j over n separations and loads (structure of arrays): the vectorised
// inner loop (AVX-512/AVX2 clones).
Vec3 screened_sum(size_t n, const double* rx, const double* ry, const double* rz,
                  const double* fx, const double* fy, const double* fz, double xi);
Vec3 screened_sum(size_t n, const float* rx, const float* ry, const float* rz,
                  const float* fx, const float* fy, const float* fz, float xi);

// Flops of one term of screened_sum, counting add, multiply, divide and square root as
// one each and an FMA as two: |r|^2 5, sqrt 1, x, x^2, x^3 3, exp 34, erfcx 71, e1 and
// e2 10, 1/r and 1/r^3 4, r.f 5, the two terms of u 12.
constexpr double kScreenedPairFlops = 145;

// Adds the real-space sum at each target to u (without the -1/(8 pi) factor). Returns
// the number of (target, source image) pairs summed, for flop counts.
long add_real_space_sum(const ShearedLattice& lattice, const FarSources& sources,
                        const std::vector<Vec3>& targets, const EwaldParameters& ewald,
                        std::vector<Vec3>& u);

} // namespace capsim
