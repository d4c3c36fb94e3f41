#pragma once
// How a drop's nodes move (membrane.law: drop). A drop's shape evolves by the normal
// velocity of its interface alone; the tangential surface flow only carries the nodes
// along the surface, and with no membrane to hold them it would crowd them where the
// surface converges and tear the mesh apart within a few strain units (what a capsule's
// elasticity prevents). So the nodes move with each drop's mean velocity plus the normal
// part of the rest (the usual choice of boundary-integral codes for drops, e.g.
// Zinchenko, Rother & Davis 1997, Phys. Fluids 9, 1493, who also add a tangential
// field that keeps the mesh regular: not needed at the small deformations tested here).
// The fluid's own velocity still enters the stresslet (capsule_diagnostics.hpp).
#include "mesh/icosphere.hpp"

#include <vector>

namespace capsim {

// u_i <- U + ((u_i - U) . n_i) n_i per capsule, U the area-weighted mean of its node
// velocities (lumped node areas), n_i the unit node normals (summed area vectors). The
// volume rate sum_i dV/dx_i . u_i is unchanged (the area vectors of a closed surface sum
// to zero), so the volume constraint acts as before.
void keep_normal_motion(const Topology& topo, int num_capsules,
                        const std::vector<Vec3>& x, std::vector<Vec3>& u);

} // namespace capsim
