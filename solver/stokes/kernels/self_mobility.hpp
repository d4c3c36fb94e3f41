#pragma once
// The self-mobility block of each node: the velocity at node i that a unit traction
// carried by node i's hat function alone induces through the free-space single layer,
//   B_i = -1/(8 pi) sum over the triangles T at i of int_T J(x_i - y) phi_i(y) dA,
// by the polar rule at the vertex (element_integrals.hpp). It is the element-scale,
// stiff part of the single-layer operator: what an implicit step keeps of it.
#include "common/vec3.hpp"
#include "mesh/icosphere.hpp"
#include "stokes/single_layer/single_layer.hpp"

#include <vector>

namespace capsim {

// B_i for the nodes of one capsule at positions x (symmetric 3x3 blocks).
std::vector<Mat3> self_mobility_blocks(const Topology& topo, const Vec3* x,
                                       const QuadratureOptions& quad);

} // namespace capsim
