#pragma once
// Free-space single-layer velocity at the mesh nodes (paper eq. 2.2 without v_inf):
//   u(x_i) = -1/(8 pi mu) sum_m int_{A_m} J(x_i - y) q(y) dA(y)
// for M capsules sharing one topology, with P1 geometry and P1 traction.
//
// Evaluation: every triangle contributes through its 3-point Gauss rule to every node
// (one dense, vectorised sum over quadrature points); for the triangles near a node that
// far rule is then replaced by an accurate one: the polar (Duffy) rule if the node is a
// vertex, adaptive subdivision otherwise. "Near" means closer than far_ratio triangle
// diameters.
#include "mesh/icosphere.hpp"

#include <vector>

namespace capsim {

struct QuadratureOptions {
  // Triangles closer than far_ratio diameters to a node get the accurate rule. 1.5 with
  // near_ratio 1 holds the free-space single layer to 2e-5 of the largest velocity, 39
  // times below the workflow's Ewald tolerances, at 0.4 of the cost of 2 and 1.5 (the
  // first defaults: docs/performance.md, "A step in situ";
  // pipeline/run_spec.py names them, so that archived runs keep their keys).
  double far_ratio = 1.5;
  // Near-singular triangles are split until each piece is near_ratio diameters away.
  double near_ratio = 1.0;
  // Deepest 1-to-4 subdivision of a near-singular triangle.
  int max_depth = 6;
  // Gauss-Legendre points of the polar rule at a vertex.
  int singular_points = 12;
};

// Where the time of one evaluation went (for benchmarks), in seconds.
struct SingleLayerTimings {
  double setup = 0; // quadrature points, near lists
  double far = 0;   // the dense far-rule sum
  double near = 0;  // accurate corrections of near triangles
  long near_pairs = 0;
};

// x, q: num_capsules * topo.num_nodes entries, capsule after capsule. u is resized.
void single_layer_velocity(const Topology& topo, int num_capsules,
                           const std::vector<Vec3>& x, const std::vector<Vec3>& q,
                           const QuadratureOptions& opts, std::vector<Vec3>& u,
                           SingleLayerTimings* timings = nullptr);

} // namespace capsim
