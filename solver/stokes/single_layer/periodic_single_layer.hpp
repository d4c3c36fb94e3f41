#pragma once
// Single-layer velocity of M capsules in a sheared periodic box (paper eqs. 2.2-2.7) by
// Ewald sums. u_i = -1/(8 pi mu) sum over triangles (all images) of int J^E(x_i - y) q
// dA:
//  - the 3-point far rule for every triangle, with J^E split into
//    - real space: every rule point and image within r_cut, screened kernel J^EI, through
//      cell lists (real_space_sum.hpp);
//    - reciprocal space: summed directly over 0 < |k| < k_cut, O((N + N_src) K), or by
//      Spectral Ewald, or directly over multipole patches (ReciprocalSum);
//  - for the triangle images near x_i (closer than far_ratio diameters): the accurate
//    free-space integral (polar rule at a vertex, adaptive subdivision otherwise) minus
//    the 3-point rule of the free-space kernel.
// Both parts use the same rule points, so the split is exact up to the Ewald tolerance
// whatever xi is: xi only trades real-space work against reciprocal-space work.
#include "mesh/icosphere.hpp"
#include "stokes/kernels/periodic_stokeslet.hpp"
#include "stokes/single_layer/single_layer.hpp"
#include "stokes/ewald/spectral_ewald.hpp"

#include <vector>

namespace capsim {

// Seconds in each stage of one evaluation (accumulated over calls), for benchmarks.
struct PeriodicTimings {
  double setup = 0, near = 0, real_space = 0, reciprocal = 0;
  long real_space_pairs = 0; // (target, source image) pairs within r_cut
  SpectralTimings spectral;  // the reciprocal stages, when Spectral Ewald is used
};

// How the reciprocal sum is taken: by Spectral Ewald when `spectral` is given (method
// spectral); else directly, over the 3-point rule points (patch_level < 0, method direct)
// or over the multipole patches of every capsule, the faces of icosphere level
// patch_level (method patches: the paper's coarse graining, section 3.1).
struct ReciprocalSum {
  SpectralEwald* spectral = nullptr;
  int patch_level = -1;
};

void periodic_single_layer_velocity(
    const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
    const std::vector<Vec3>& q, const ShearedLattice& lattice,
    const EwaldParameters& ewald, const QuadratureOptions& quad, std::vector<Vec3>& u,
    ReciprocalSum reciprocal = {}, PeriodicTimings* timings = nullptr);

} // namespace capsim
