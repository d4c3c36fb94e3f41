#pragma once
// Freund's (2007) volume constraint of the time loop (paper eq. 3.2 conserves volume only
// to the mesh's accuracy): the drift removed after each step, and the rate removed from
// each stage's velocity so that the schemes integrate a volume-preserving field.
#include "mesh/icosphere.hpp"

#include <vector>

namespace capsim {

// Moves each capsule's nodes along their normals by (V0 - V)/A until the relative volume
// error is below 1e-13 (three or four passes). Returns each capsule's (V - V0)/V0 found
// before correcting: the volume drift of the step that is being corrected.
std::vector<double> enforce_volume(const Topology& topo, int num_capsules,
                                   std::vector<Vec3>& x,
                                   const std::vector<double>& volume0);

// Removes from the node velocities u of each capsule the rate of change of its enclosed
// volume: u_i <- u_i - r n_i along the unit node normals n_i, with r such that
// dV/dt = sum_i dV/dx_i . u_i = 0 (dV/dx_i = 1/6 of the node's summed area vectors). The
// boundary-element velocity changes the discrete volume at a rate set by the mesh
// (about 0.4 % per unit strain at level 2); enforce_volume alone removes that drift after
// each step, a splitting whose global error is first order in dt whatever the scheme.
// Applied to every stage's velocity, the scheme integrates a volume-preserving field at
// its own order and enforce_volume removes only the O(dt^3) rest (docs/method.md).
void remove_volume_rate(const Topology& topo, int num_capsules,
                        const std::vector<Vec3>& x, std::vector<Vec3>& u);

} // namespace capsim
