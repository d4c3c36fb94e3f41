#pragma once
// The surface of M capsules as P1 triangles with their loads, and the far-rule (3-point)
// quadrature points of every triangle as structure-of-arrays, the input of the dense
// sums.
#include "mesh/icosphere.hpp"
#include "stokes/quadrature/element_integrals.hpp"
#include "stokes/quadrature/near_corrections.hpp"
#include "stokes/single_layer/single_layer.hpp"

#include <vector>

namespace capsim {

struct FarSources {
  std::vector<double> y[3]; // point positions
  std::vector<double> f[3]; // weight * area * q at the point
  size_t size() const { return y[0].size(); }
};

// Triangle `global_triangle` (capsule * T + local index) with its node positions and
// loads.
TriangleLoad triangle_load(const Topology& topo, const std::vector<Vec3>& x,
                           const std::vector<Vec3>& q, int global_triangle);

FarSources far_sources(const std::vector<TriangleLoad>& loads);

// How many far-rule points (triangle_rule_3) M capsules of mesh `topo` have: the sources
// of the dense sums, whose count the Ewald set-up balances its cost against.
long far_rule_points(const Topology& topo, int num_capsules);

// Which vertex (0-2) of triangle `t_global` the node `node` (both global, capsule after
// capsule) is, or -1.
int vertex_index(const Topology& topo, int node, int t_global);

// The quadrature options as the plain rule that host-device code takes (gl must outlive
// it).
NearRule near_rule(const QuadratureOptions& o, const LineRule& gl);

} // namespace capsim
