#pragma once
// Free-space double-layer velocity for M capsules sharing one topology, P1 geometry and
// P1 density u (the surface velocity), in the normalisation of the single layer
// (single_layer.hpp, paper eq. 2.2):
//   K[u](x) = 1/(8 pi) sum_m PV int_{A_m} u_i(y) T_ijk(x - y) n_k(y) dA(y),
//   T_ijk(r) = -6 r_i r_j r_k / |r|^5,   r = x - y (target minus source),
// n the outward unit normal. This is Pozrikidis's stresslet T_ijk(x^) = -6 x^_i x^_j
// x^_k / |x^|^5 (1992, "Boundary integral and singularity methods", ch. 2) with his x^ =
// y - x (integration point minus field point) reversed, so K has the opposite sign of his
// (1/(8 pi)) int u T n dS. (Equation numbers of the book could not be checked here; the
// signs below are derived from the divergence theorem and verified by
// tests/cpp/test_double_layer.cpp.)
//
// Gauss's identity: div_y of r_i r_j r_k / |r|^5 vanishes, so the integral reduces to
// one over a small sphere about x, where it is isotropic, with trace -6 times the flux of
// r/|r|^3 (-4 pi inside, -2 pi on a smooth part of the surface, 0 outside):
//   1/(8 pi) int T_ijk(x - y) n_k(y) dA(y) = d_ij inside, d_ij/2 on the surface
//   (principal value), 0 outside.
// A rigid-body motion v likewise gives K[v] = v/2 on its own surface and 0 outside it
// (Lorentz reciprocal theorem: v is a stress-free Stokes flow inside).
//
// With this K the drop/capsule boundary-integral equation (Pozrikidis 1992, ch. 5: the
// representation of a drop of viscosity lambda mu in fluid of viscosity mu, written in
// his convention with the factor (1 - lambda)/(4 pi (1 + lambda)) in front of PV int u T
// n dS) reads, for x on the surface,
//   u - kappa K[u] = 2/(1 + lambda) (u_inf + u_SL),  kappa = 2 (lambda - 1)/(lambda + 1),
// u_SL the single-layer velocity of single_layer.hpp; see second_kind_solve.hpp.
//
// Evaluation at the nodes (singularity subtraction): for node x_i of capsule c,
//   8 pi K[u](x_i) = int_{A_c} (u(y) - u(x_i)) T n dA + sum_{m != c} int_{A_m} u T n dA
//                    + 4 pi u(x_i),
// using the on-surface identity for the subtracted constant, so a constant (a rigid
// translation) is mapped exactly to u/2. The subtracted integrand is bounded. On the
// triangles that have x_i as a vertex it vanishes identically: they are flat, so r lies
// in their plane and r . n = 0. Every other triangle gets the 3-point Gauss rule
// (triangle_rule_3), and the ones closer than far_ratio diameters get adaptive
// subdivision instead (for_each_adaptive_point, element_integrals.hpp), the same near
// lists and options as the single layer.
#include "mesh/icosphere.hpp"
#include "stokes/double_layer/ewald_stresslet.hpp"
#include "stokes/quadrature/element_integrals.hpp"
#include "stokes/single_layer/single_layer.hpp"

#include <vector>

namespace capsim {

// u . T(r) . a = -6 (u . r)(a . r) r / |r|^5: the stresslet contracted with the density
// u and the (area-weighted) normal a.
CAPSIM_HD Vec3 stresslet_apply(Vec3 r, Vec3 u, Vec3 a) {
  const double r2 = dot(r, r), rinv = 1.0 / std::sqrt(r2);
  const double s = -6.0 * dot(u, r) * dot(a, r) * rinv * rinv * rinv * rinv * rinv;
  return s * r;
}

// The correction of the far rule for triangle `load` (density u in load.q, unit normal n,
// area `area`) near target x: its accurate integral minus its 3-point rule, of
// (u(y) - sub) . T(x - y) . n. The accurate integral is adaptive subdivision, or nothing
// when x is one of the triangle's vertices (the flat triangle's integrand vanishes
// there). Host-device, so that a CUDA path applies the same quadrature.
CAPSIM_HD Vec3 double_layer_near_correction(Vec3 x, bool is_vertex, TriangleLoad load,
                                            Vec3 n, Vec3 sub, double area,
                                            double near_ratio, int max_depth) {
  for (auto& q : load.q)
    q -= sub;
  Vec3 sum;
  if (!is_vertex)
    for_each_adaptive_point(x, load, near_ratio, max_depth,
                            [&](Vec3 r, Vec3 w) { sum += stresslet_apply(r, w, n); });
  for_each_rule_point(x, load, triangle_rule_3(), area,
                      [&](Vec3 r, Vec3 w) { sum -= stresslet_apply(r, w, n); });
  return sum;
}

// The same correction as a linear map of the vertex densities: m[v] (symmetric, xx, yy,
// zz, xy, xz, yz) such that the correction is sum_v m[v] (q_v - sub). One quadrature pass
// with a load whose q_v are the unit vectors e_v, so that each point's weighted density
// is w (l_0, l_1, l_2) (the subdivision depends on the geometry alone): set up once per
// geometry, the correction of every GMRES iteration is then 18 numbers a vertex pair.
CAPSIM_HD void double_layer_near_matrices(Vec3 x, bool is_vertex, const Vec3 p[3], Vec3 n,
                                          double area, double near_ratio, int max_depth,
                                          double m[3][6]) {
  const TriangleLoad load{{p[0], p[1], p[2]}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (int v = 0; v < 3; ++v)
    for (int c = 0; c < 6; ++c)
      m[v][c] = 0;
  // u . T(r) . n = -6 (n . r)/|r|^5 (r r^T) u (stresslet_apply).
  auto add = [&](Vec3 r, Vec3 w, double sign) {
    const double r2 = dot(r, r), rinv = 1.0 / std::sqrt(r2);
    const double s = -6.0 * sign * dot(n, r) * rinv * rinv * rinv * rinv * rinv;
    const double rr[6] = {r.x * r.x, r.y * r.y, r.z * r.z,
                          r.x * r.y, r.x * r.z, r.y * r.z};
    const double wv[3] = {s * w.x, s * w.y, s * w.z};
    for (int v = 0; v < 3; ++v)
      for (int c = 0; c < 6; ++c)
        m[v][c] += wv[v] * rr[c];
  };
  if (!is_vertex)
    for_each_adaptive_point(x, load, near_ratio, max_depth,
                            [&](Vec3 r, Vec3 w) { add(r, w, 1.0); });
  for_each_rule_point(x, load, triangle_rule_3(), area,
                      [&](Vec3 r, Vec3 w) { add(r, w, -1.0); });
}

// The near correction from its matrices (double_layer_near_matrices, 18 numbers, vertex
// after vertex) and the triangle's vertex densities u: sum_v m[v] (u_v - sub).
CAPSIM_HD Vec3 double_layer_near_apply(const double* m, const Vec3 u[3], Vec3 sub) {
  return symmetric_matrix_apply(m, u[0] - sub) +
         symmetric_matrix_apply(m + 6, u[1] - sub) +
         symmetric_matrix_apply(m + 12, u[2] - sub);
}

// What the double layer's quadratures need of every triangle of M capsules (global
// triangle index, capsule after capsule): outward unit normal, area, centroid and
// diameter, and the 3-point rule's points y and vectors a = w A n, triangle after
// triangle. Shared by the free-space and the periodic double layer.
struct DoubleLayerTriangles {
  std::vector<Vec3> unit_normal, centroid;
  std::vector<double> area, diameter;
  std::vector<Vec3> y, a;
};

// x: num_capsules * topo.num_nodes positions (else std::invalid_argument).
DoubleLayerTriangles double_layer_triangles(const Topology& topo, int num_capsules,
                                            const std::vector<Vec3>& x);

// The near correction's matrices (double_layer_near_matrices, 18 numbers into m) of
// node i of x (as above) and the image of triangle t moved by `shift` (a lattice vector;
// exactly zero for the triangle itself, of which node i may be a vertex). Shared by the
// free-space and the periodic double layer's set-up.
void double_layer_near_pair_matrices(const Topology& topo, const std::vector<Vec3>& x,
                                     const DoubleLayerTriangles& tri,
                                     const QuadratureOptions& opts, int i, int t,
                                     Vec3 shift, double* m);

// The double layer of one geometry, set up once and applied to many densities (the
// GMRES iterations of second_kind_solve.hpp share one geometry).
class DoubleLayer {
public:
  // x: num_capsules * topo.num_nodes positions, capsule after capsule (copied, as is
  // the topology).
  DoubleLayer(const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
              const QuadratureOptions& opts);

  int num_nodes() const { return int(x_.size()); }

  // k = K[u] at the nodes (u: one vector per node, else std::invalid_argument). With
  // subtract = false the self capsule is integrated without singularity subtraction (the
  // plain principal value of the polyhedron, for testing Gauss's identity on the
  // surface).
  void apply(const std::vector<Vec3>& u, std::vector<Vec3>& k,
             bool subtract = true) const;

  // k = K[u] at points off the surfaces (no subtraction): near triangles by adaptive
  // subdivision. A target closer to a surface than near_ratio * 2^-max_depth triangle
  // diameters is not resolved.
  void apply_at(const std::vector<Vec3>& targets, const std::vector<Vec3>& u,
                std::vector<Vec3>& k) const;

private:
  // The density u at every triangle's far-rule points (structure of arrays).
  void rule_densities(const std::vector<Vec3>& u, std::vector<double> (&ug)[3]) const;

  Topology topo_;
  int num_capsules_;
  std::vector<Vec3> x_;
  QuadratureOptions opts_;
  DoubleLayerTriangles tri_;
  // tri_'s y and a as structure of arrays, for the vectorised far sums.
  std::vector<double> y_[3], a_[3];
  // Per node: sum over its own capsule's 3-point rule of T(x_i - y_g) . a_g (symmetric;
  // xx, yy, zz, xy, xz, yz), the far part of the subtracted term.
  std::vector<double> self_[6];
  std::vector<int> near_offset_, near_triangle_; // the near lists of the nodes
  // Per near pair the correction's matrices (double_layer_near_matrices), 18 numbers.
  std::vector<double> near_matrix_;
};

// One-shot form: k = K[u] at the nodes of M capsules.
void double_layer_velocity(const Topology& topo, int num_capsules,
                           const std::vector<Vec3>& x, const std::vector<Vec3>& u,
                           const QuadratureOptions& opts, std::vector<Vec3>& k);

} // namespace capsim
