#pragma once
// Real-space part of the Ewald sum (paper eqs. 2.4, 2.6): at every target x,
//   sum over all images of all far-rule points y with |x - y| < r_cut of J^EI(x - y) f.
// Per target the neighbours are gathered from cell lists into a contiguous buffer, then
// summed in one vectorised loop (the kernel has no branches; see fast_special.hpp).
#include "stokes/periodic_cells.hpp"
#include "stokes/periodic_stokeslet.hpp"
#include "stokes/triangle_sources.hpp"

#include <vector>

namespace capsim {

// Adds the real-space sum at each target to u (without the -1/(8 pi) factor). Returns
// the number of (target, source image) pairs summed, for flop counts.
long add_real_space_sum(const ShearedLattice& lattice, const FarSources& sources,
                        const std::vector<Vec3>& targets, const EwaldParameters& ewald,
                        std::vector<Vec3>& u);

} // namespace capsim
