#pragma once
// The reciprocal-space (smooth) part of the Ewald sum, paper eq. 2.3 second term:
//   u_i += (8 pi / V) sum_{0 < |k| < k_cut} J^EII(k) Re[exp(i k . x_i) sum_g f_g exp(-i k
//   . y_g)]
// evaluated directly, O((N_targets + N_sources) K): the reference for Spectral Ewald.
// Half the wave vectors are summed (k and -k give the same), and the phase factors come
// from per-point tables of exp(i m b_d . x) by complex products, not sines and cosines.
#include "stokes/ewald/multipole_patches.hpp"
#include "stokes/kernels/periodic_stokeslet.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <vector>

namespace capsim {

// One real-space pair (the screened Stokeslet) costs about as much as ten (point, wave
// vector) terms of these sums, counted over the full set of wave vectors (measured at
// M = 27, level 3, 1e-4 on two cores: 5.1 ns per pair, 0.52 ns per term): the pair_cost
// with which method `direct` balances xi (balanced_xi).
constexpr double kRealPairCost = 10.0;

// Adds the reciprocal-space sum (without the -1/(8 pi) factor) to u at the targets x.
void ewald_reciprocal_direct(const ShearedLattice& g, const std::vector<Vec3>& x,
                             const FarSources& s, const EwaldParameters& p,
                             std::vector<Vec3>& u);

// The same sum with every source capsule coarse-grained into multipole patches (paper
// eqs. 3.3-3.6): a patch at c with force F and first moment D acts as
// J^EII(x - c) F - d_l J^EII(x - c) D_.l, so its structure-factor terms are
// F exp(-i k.c) and -i (D k) exp(-i k.c). Method `patches`.
void ewald_reciprocal_patches(const ShearedLattice& g, const std::vector<Vec3>& x,
                              const std::vector<PatchMoments>& patches,
                              const EwaldParameters& p, std::vector<Vec3>& u);

} // namespace capsim
