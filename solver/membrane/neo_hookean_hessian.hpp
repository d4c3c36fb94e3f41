#pragma once
// The second derivative of the neo-Hookean element energy (neo_hookean.hpp) with respect
// to its three node positions: what an implicit time step linearises the membrane load
// with. With e1 = x1 - x0, e2 = x2 - x0, W = c (i1 - 3 + det G / det g), c = Gs A0 / 2,
// i1 = G^ab g_ab and det g = g11 g22 - g12^2, the gradient is
//   f_a = dW/de_a = c (2 G^ab e_b + d_inv D_a),   D_a = d det g / d e_a,
// d_inv = -det G / det g^2, so
//   dfa/de_b = c (2 G^ab I + d_inv dD_a/de_b + 2 det G / det g^3 D_a D_b^T)
// and the node blocks follow from x0 = -(e1 + e2) moves.
#include "membrane/neo_hookean.hpp"

#include <Eigen/Dense>

namespace capsim {

using Matrix9 = Eigen::Matrix<double, 9, 9>;

// d^2 W_e / dx_i dx_j for the element's nodes i, j in 0..2, as 3x3 blocks (3 i + a,
// 3 j + b).
inline Matrix9 neo_hookean_element_hessian(const ElementReference& ref, double gs,
                                           Vec3 x0, Vec3 x1, Vec3 x2) {
  using M3 = Eigen::Matrix3d;
  using V3 = Eigen::Vector3d;
  const V3 e1(x1.x - x0.x, x1.y - x0.y, x1.z - x0.z);
  const V3 e2(x2.x - x0.x, x2.y - x0.y, x2.z - x0.z);
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
  const double det = g11 * g22 - g12 * g12, c = 0.5 * gs * ref.area0;
  const double d_inv = -ref.det_g0 / (det * det);
  const double d_inv2 = 2.0 * ref.det_g0 / (det * det * det);
  const V3 d1 = 2.0 * (g22 * e1 - g12 * e2), d2 = 2.0 * (g11 * e2 - g12 * e1);
  const M3 id = M3::Identity();
  const M3 dd11 = 2.0 * (g22 * id - e2 * e2.transpose());
  const M3 dd22 = 2.0 * (g11 * id - e1 * e1.transpose());
  const M3 dd12 = 2.0 * (2.0 * e1 * e2.transpose() - e2 * e1.transpose() - g12 * id);
  const M3 h11 =
      c * (2.0 * ref.ginv11 * id + d_inv * dd11 + d_inv2 * d1 * d1.transpose());
  const M3 h22 =
      c * (2.0 * ref.ginv22 * id + d_inv * dd22 + d_inv2 * d2 * d2.transpose());
  const M3 h12 =
      c * (2.0 * ref.ginv12 * id + d_inv * dd12 + d_inv2 * d1 * d2.transpose());
  const M3 h21 = h12.transpose();
  Matrix9 h;
  h.block<3, 3>(3, 3) = h11;
  h.block<3, 3>(3, 6) = h12;
  h.block<3, 3>(6, 3) = h21;
  h.block<3, 3>(6, 6) = h22;
  h.block<3, 3>(0, 3) = -(h11 + h21);
  h.block<3, 3>(0, 6) = -(h12 + h22);
  h.block<3, 3>(3, 0) = -(h11 + h12);
  h.block<3, 3>(6, 0) = -(h21 + h22);
  h.block<3, 3>(0, 0) = h11 + h12 + h21 + h22;
  return h;
}

} // namespace capsim
