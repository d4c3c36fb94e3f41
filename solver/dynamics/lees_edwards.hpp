#pragma once
// Lees-Edwards boundary handling for a sheared periodic box: capsules are kept whole and
// moved, as a whole, by a lattice vector of the current (sheared) lattice whenever their
// centroid leaves the primary cell (fractional coordinates in [0, 1)). Crossing the
// gradient (y) boundary therefore also shifts x by the strain offset s L, and, through
// v_inf = (y, 0, 0) at the new position, changes the capsule's imposed velocity by
// gammadot L: the Lees-Edwards conditions.
#include "mesh/icosphere.hpp"
#include "stokes/cells/sheared_lattice.hpp"

#include <vector>

namespace capsim {

// Returns the number of capsules moved.
int remap_capsules(const Topology& topo, int num_capsules, const ShearedLattice& lattice,
                   std::vector<Vec3>& x);

// Smallest distance between nodes of different capsules, or of a capsule and its own
// periodic image, over every image (capsule_a == capsule_b for the latter): a cheap,
// conservative proxy for the surface gap, used to stop a run whose capsules overlap.
// Exact where it is below `reach`; pairs of capsules whose bounding spheres stay `reach`
// apart, and nodes outside the other capsule's bounding sphere widened by `reach`, are
// not examined (a distance of `reach` or more may come back as 1e300).
struct ClosestApproach {
  double distance = 1e300;
  int capsule_a = -1, capsule_b = -1;
};
ClosestApproach closest_approach(const Topology& topo, int num_capsules,
                                 const ShearedLattice& lattice,
                                 const std::vector<Vec3>& x, double reach);

} // namespace capsim
