#pragma once
// Neo-Hookean membrane element (paper eqs. 2.8-2.11, weak form 3.1) on a linear (P1)
// triangle. With reference edges E1, E2 and deformed edges e1, e2, the metric tensors are
// G_ab = E_a . E_b and g_ab = e_a . e_b; then l1^2 + l2^2 = tr(G^-1 g) and
// (l1 l2)^2 = det g / det G. The element energy is A0 * w_s, and its exact gradient with
// respect to the three node positions is the nodal force of the FEM weak form.
#include "common/vec3.hpp"

namespace capsim {

// What an element needs of its reference (stress-free) state.
struct ElementReference {
  double ginv11 = 0, ginv12 = 0, ginv22 = 0; // inverse reference metric G^-1
  double det_g0 = 0;                         // det G = (2 A0)^2
  double area0 = 0;                          // reference area A0
};

CAPSIM_HD ElementReference make_element_reference(Vec3 X0, Vec3 X1, Vec3 X2) {
  Vec3 e1 = X1 - X0, e2 = X2 - X0;
  double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
  double det = g11 * g22 - g12 * g12;
  ElementReference r;
  r.ginv11 = g22 / det;
  r.ginv12 = -g12 / det;
  r.ginv22 = g11 / det;
  r.det_g0 = det;
  r.area0 = 0.5 * std::sqrt(det);
  return r;
}

// Returns the element energy A0 * w_s (eq. 2.11) and adds its gradient dW/dx_k to
// grad[k].
CAPSIM_HD double neo_hookean_element(const ElementReference& ref, double gs, Vec3 x0,
                                     Vec3 x1, Vec3 x2, Vec3 grad[3]) {
  Vec3 e1 = x1 - x0, e2 = x2 - x0;
  double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
  double det = g11 * g22 - g12 * g12;
  double i1 = ref.ginv11 * g11 + 2.0 * ref.ginv12 * g12 + ref.ginv22 * g22; // l1^2 + l2^2
  double inv_j2 = ref.det_g0 / det;                                         // 1/(l1 l2)^2
  double c = 0.5 * gs * ref.area0;
  double energy = c * (i1 - 3.0 + inv_j2);
  // d i1/d e1 = 2 (G^11 e1 + G^12 e2);  d det/d e1 = 2 (g22 e1 - g12 e2), and symmetric.
  Vec3 di1_de1 = 2.0 * (ref.ginv11 * e1 + ref.ginv12 * e2);
  Vec3 di1_de2 = 2.0 * (ref.ginv12 * e1 + ref.ginv22 * e2);
  Vec3 ddet_de1 = 2.0 * (g22 * e1 - g12 * e2);
  Vec3 ddet_de2 = 2.0 * (g11 * e2 - g12 * e1);
  double dinv = -inv_j2 / det; // d(1/J^2)/d det
  Vec3 f1 = c * (di1_de1 + dinv * ddet_de1);
  Vec3 f2 = c * (di1_de2 + dinv * ddet_de2);
  grad[0] -= f1 + f2;
  grad[1] += f1;
  grad[2] += f2;
  return energy;
}

} // namespace capsim
