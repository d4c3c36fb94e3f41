#pragma once
// Single-layer velocity of M capsules in a sheared periodic box (paper eqs. 2.2-2.7) by
// plain Ewald sums: the reference ("direct") method that the fast methods are measured
// against. u_i = -1/(8 pi mu) sum over triangles (all images) of int J^E(x_i - y) q dA:
//  - real space: every 3-point far-rule point and every image within r_cut, with the
//    screened kernel J^EI; for the triangle images near x_i (closer than far_ratio
//    diameters) that is replaced by the accurate free-space integral (polar rule at a
//    vertex, adaptive subdivision otherwise) plus a 7-point rule of the smooth J^EI - J;
//  - reciprocal space: structure factors S(k) = sum_g f_g exp(-i k . y_g) over the same
//    points, for every wave vector 0 < |k| < k_cut.
// The real-space sums run over cell lists when the box holds at least 5 x 3 x 3 cells of
// side r_cut (otherwise over all points and images). The reciprocal part is summed
// directly, O((N + N_src) K), or by Spectral Ewald when `spectral` is given.
#include "mesh/icosphere.hpp"
#include "stokes/periodic_stokeslet.hpp"
#include "stokes/single_layer.hpp"
#include "stokes/spectral_ewald.hpp"

#include <vector>

namespace capsim {

void periodic_single_layer_velocity(const Topology& topo, int num_capsules,
                                    const std::vector<Vec3>& x,
                                    const std::vector<Vec3>& q,
                                    const ShearedLattice& lattice,
                                    const EwaldParameters& ewald,
                                    const QuadratureOptions& quad, std::vector<Vec3>& u,
                                    SpectralEwald* spectral = nullptr);

} // namespace capsim
