#pragma once
// The membrane's fields of a snapshot (paper figs. 3 and 9): the principal tensions and
// the area dilatation of every element, and at each node the means of the tensions over
// its elements, weighted by their reference areas.
#include "io/xdmf_snapshot.hpp"
#include "membrane/membrane_forces.hpp"

#include <vector>

namespace capsim {

// Fills frame's tension_max, tension_min (per node), area_dilatation and
// element_tension_max, element_tension_min (per element) for num_capsules capsules at x.
void add_membrane_fields(const Membrane& membrane, int num_capsules,
                         const std::vector<Vec3>& x, SnapshotFrame& frame);

} // namespace capsim
