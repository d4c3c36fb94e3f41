#pragma once
// The second derivative of the membrane element energy (neo_hookean.hpp, and its
// relaxation tension_field.hpp) with respect to its three node positions: what an
// implicit time step linearises the membrane load with. Both energies are functions of
// the invariants i1 = G^ab g_ab = L1 + L2 and J^2 = det g / det G = L1 L2 of the edges
// e = (e1, e2) = (x1 - x0, x2 - x0), so the Hessians are formed in the six edge
// coordinates from
//   d i1/de_a = 2 G^ab e_b,            d^2 i1/de_a de_b = 2 G^ab I,
//   d J^2/de_a = D_a / det G,          d^2 J^2/de_a de_b = (dD_a/de_b) / det G,
// D_a = d det g / de_a, and carried to the nodes by x0 = -(e1 + e2) moves.
// Neo-Hookean (eq. 2.11), W = c (i1 - 3 + 1/J^2), c = Gs A0 / 2:
//   d^2 W = c (d^2 i1 - d^2 J^2 / J^4 + 2 dJ^2 dJ^2^T / J^6).
// Wrinkled (tension_field.hpp), W = c f(L1), f = L1 + 2 L1^(-1/2) - 3: differentiating
// (L1 - L2) dL1 = L1 d i1 - d J^2 once more, with dL2 = d i1 - dL1,
//   (L1 - L2) d^2 L1 = d i1 dL1^T + dL1 d i1^T - 2 dL1 dL1^T + L1 d^2 i1 - d^2 J^2,
//   d^2 W = c (f''(L1) dL1 dL1^T + f'(L1) d^2 L1).
// Slack: 0. The relaxed energy is C1, so its Hessian jumps across the region borders; a
// W-method (the imex scheme) keeps its order with any Jacobian.
#include "membrane/hessian_part.hpp"
#include "membrane/tension_field.hpp"

#include <Eigen/Dense>

namespace capsim {

using Matrix9 = Eigen::Matrix<double, 9, 9>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// The invariants' first and second derivatives in the edge coordinates (e1, e2).
struct EdgeInvariants {
  Vector6 di1, dj2;
  Matrix6 ddi1, ddj2;
  double j2 = 1;
};

inline EdgeInvariants edge_invariants(const ElementReference& ref,
                                      const Eigen::Vector3d& e1,
                                      const Eigen::Vector3d& e2) {
  using M3 = Eigen::Matrix3d;
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
  const M3 id = M3::Identity();
  EdgeInvariants v;
  v.j2 = (g11 * g22 - g12 * g12) / ref.det_g0;
  v.di1 << 2.0 * (ref.ginv11 * e1 + ref.ginv12 * e2),
      2.0 * (ref.ginv12 * e1 + ref.ginv22 * e2);
  v.dj2 << 2.0 * (g22 * e1 - g12 * e2), 2.0 * (g11 * e2 - g12 * e1);
  v.dj2 /= ref.det_g0;
  v.ddi1 << 2.0 * ref.ginv11 * id, 2.0 * ref.ginv12 * id, 2.0 * ref.ginv12 * id,
      2.0 * ref.ginv22 * id;
  const M3 dd12 = 2.0 * (2.0 * e1 * e2.transpose() - e2 * e1.transpose() - g12 * id);
  v.ddj2 << 2.0 * (g22 * id - e2 * e2.transpose()), dd12, dd12.transpose(),
      2.0 * (g11 * id - e1 * e1.transpose());
  v.ddj2 /= ref.det_g0;
  return v;
}

// d^2 W/dx_i dx_j (3 i + a, 3 j + b) from d^2 W/de de with e1 = x1 - x0, e2 = x2 - x0.
inline Matrix9 node_hessian(const Matrix6& h) {
  Eigen::Matrix<double, 6, 9> p = Eigen::Matrix<double, 6, 9>::Zero();
  for (int a = 0; a < 2; ++a) { // de_a = dx_{a+1} - dx_0
    p.block<3, 3>(3 * a, 0) = -Eigen::Matrix3d::Identity();
    p.block<3, 3>(3 * a, 3 * (a + 1)) = Eigen::Matrix3d::Identity();
  }
  return p.transpose() * h * p;
}

inline Matrix6 neo_hookean_edge_hessian(const ElementReference& ref, double gs,
                                        const EdgeInvariants& v) {
  const double c = 0.5 * gs * ref.area0, j4 = v.j2 * v.j2;
  return c * (v.ddi1 - v.ddj2 / j4 + (2.0 / (j4 * v.j2)) * v.dj2 * v.dj2.transpose());
}

inline Matrix6 wrinkled_edge_hessian(const ElementReference& ref, double gs,
                                     const SquaredStretches& s, const EdgeInvariants& v) {
  if (!(s.gap > 0)) // L1 within round-off of 1: the force's limit is zero there
    return Matrix6::Zero();
  const double l1 = s.l1sq, inv_root = 1.0 / std::sqrt(l1);
  const double f1 = 1.0 - inv_root * inv_root * inv_root;      // f'(L1)
  const double f2 = 1.5 * inv_root * inv_root * inv_root / l1; // f''(L1)
  const Vector6 dl = (l1 * v.di1 - v.dj2) / s.gap;
  const Matrix6 ddl = (v.di1 * dl.transpose() + dl * v.di1.transpose() -
                       2.0 * dl * dl.transpose() + l1 * v.ddi1 - v.ddj2) /
                      s.gap;
  return 0.5 * gs * ref.area0 * (f2 * dl * dl.transpose() + f1 * ddl);
}

// d^2 W_e / de de of the element's energy, the paper's (eq. 2.11) or the relaxed one
// (tension_field_element), in the edge coordinates e1 = x1 - x0, e2 = x2 - x0.
inline Matrix6 membrane_edge_hessian(const ElementReference& ref, double gs,
                                     bool wrinkling, Vec3 x0, Vec3 x1, Vec3 x2) {
  const Eigen::Vector3d e1(x1.x - x0.x, x1.y - x0.y, x1.z - x0.z);
  const Eigen::Vector3d e2(x2.x - x0.x, x2.y - x0.y, x2.z - x0.z);
  if (!wrinkling)
    return neo_hookean_edge_hessian(ref, gs, edge_invariants(ref, e1, e2));
  const SquaredStretches s = squared_stretches(ref, e1.dot(e1), e1.dot(e2), e2.dot(e2));
  switch (tension_state(s)) {
  case TensionState::taut:
    return neo_hookean_edge_hessian(ref, gs, edge_invariants(ref, e1, e2));
  case TensionState::wrinkled:
    return wrinkled_edge_hessian(ref, gs, s, edge_invariants(ref, e1, e2));
  case TensionState::slack:
    break;
  }
  return Matrix6::Zero();
}

// The positive semidefinite part of a symmetric Hessian: its negative eigenvalues set
// to zero. Where an element is compressed, the paper's energy is not convex (the
// membrane buckles there, at the element scale without bending): its Hessian has
// negative eigenvalues, growing modes of the load's linearisation J. The implicit step
// divides by (1 - gamma dt lambda) for each mode of J, so a growing mode with
// dt lambda near 1/gamma is amplified without bound (at Ca 0.05, level 4, fixed steps
// of 0.04-0.06 blew up within 1.4 strain units). Without the negative part the growing
// modes are left to the explicit part, which follows them at their own rate, and the
// Rosenbrock-W step keeps its order, which holds for any J (docs/method.md).
// Compiled once (neo_hookean_hessian.cpp): Eigen's eigensolver costs about 8 s of
// compiling in every file that instantiates it.
Matrix6 positive_part(const Matrix6& h);

// d^2 W_e / dx_i dx_j for the element's nodes i, j in 0..2, as 3x3 blocks (3 i + a,
// 3 j + b).
inline Matrix9 neo_hookean_element_hessian(const ElementReference& ref, double gs,
                                           Vec3 x0, Vec3 x1, Vec3 x2) {
  return node_hessian(membrane_edge_hessian(ref, gs, false, x0, x1, x2));
}

// The same for the relaxed energy (tension_field_element).
inline Matrix9 tension_field_element_hessian(const ElementReference& ref, double gs,
                                             Vec3 x0, Vec3 x1, Vec3 x2) {
  return node_hessian(membrane_edge_hessian(ref, gs, true, x0, x1, x2));
}

// The Hessian of membrane_element.
inline Matrix9 membrane_element_hessian(const ElementReference& ref, double gs,
                                        bool wrinkling, Vec3 x0, Vec3 x1, Vec3 x2,
                                        HessianPart part = HessianPart::exact) {
  const Matrix6 h = membrane_edge_hessian(ref, gs, wrinkling, x0, x1, x2);
  return node_hessian(part == HessianPart::positive ? positive_part(h) : h);
}

} // namespace capsim
