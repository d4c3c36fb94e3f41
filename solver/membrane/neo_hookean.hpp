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

// The squared principal stretches L1 = l1^2 >= L2 = l2^2 of an element, the eigenvalues
// of M = G^-1 g, with their gap L1 - L2 and J^2 = (l1 l2)^2 = det g / det G. The gap
// comes from M's entries: from the invariants, (l1^2 + l2^2)^2 / 4 - J^2 would cancel to
// round-off noise near isotropy. L2 = J^2 / L1 keeps its digits when l2 is small.
struct SquaredStretches {
  double l1sq = 1, l2sq = 1, gap = 0, j2 = 1;
};

CAPSIM_HD SquaredStretches squared_stretches(const ElementReference& ref, double g11,
                                             double g12, double g22) {
  double m11 = ref.ginv11 * g11 + ref.ginv12 * g12,
         m12 = ref.ginv11 * g12 + ref.ginv12 * g22;
  double m21 = ref.ginv12 * g11 + ref.ginv22 * g12,
         m22 = ref.ginv12 * g12 + ref.ginv22 * g22;
  SquaredStretches s;
  s.gap = std::sqrt(std::fmax(0.0, (m11 - m22) * (m11 - m22) + 4.0 * m12 * m21));
  s.l1sq = 0.5 * (m11 + m22 + s.gap);
  s.j2 = (g11 * g22 - g12 * g12) / ref.det_g0;
  s.l2sq = s.j2 / s.l1sq;
  return s;
}

// The principal tensions T1 >= T2 of the element (Cauchy, per unit deformed length, in
// units of Gs) and its area dilatation J = l1 l2. From eq. 2.10 with w_s of eq. 2.11:
// T_a = (1 / l_b) dw_s/dl_a = Gs (l_a^2 - 1 / J^2) / J (a != b).
struct ElementTensions {
  double t1 = 0, t2 = 0; // T1 >= T2, over Gs
  double dilatation = 1; // J = deformed area / reference area
};

CAPSIM_HD ElementTensions neo_hookean_tensions(const ElementReference& ref, Vec3 x0,
                                               Vec3 x1, Vec3 x2) {
  Vec3 e1 = x1 - x0, e2 = x2 - x0;
  const SquaredStretches s =
      squared_stretches(ref, dot(e1, e1), dot(e1, e2), dot(e2, e2));
  const double j = std::sqrt(s.j2);
  ElementTensions t;
  t.t1 = (s.l1sq - 1.0 / s.j2) / j;
  t.t2 = (s.l2sq - 1.0 / s.j2) / j;
  t.dilatation = j;
  return t;
}

} // namespace capsim
