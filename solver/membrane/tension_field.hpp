#pragma once
// The relaxed (tension-field) neo-Hookean element, key membrane.wrinkling (off by
// default). A membrane without bending stiffness cannot carry a compressive tension: it
// buckles at a scale that nothing in the model sets, on a mesh the element scale (Lac,
// Barthes-Biesel, Pelekasis & Tsamopoulos 2004). Tension-field theory replaces the
// strain energy w by its relaxation, the least mean energy of any fine wrinkling with
// the same mean deformation (Pipkin 1986; Steigmann 1990). For the neo-Hookean w_s of
// eq. 2.11, with L1 = l1^2 >= L2 = l2^2 (squared_stretches) and c = Gs / 2:
//   taut      L1 L2^2 >= 1 (T2 >= 0):  w = c (L1 + L2 + 1 / (L1 L2) - 3)   (eq. 2.11)
//   wrinkled  L1 > 1 > L1 L2^2:        w = c (L1 + 2 / sqrt(L1) - 3)
//   slack     L1 <= 1:                 w = 0
// T2 = Gs (L2 - 1 / (L1 L2)) / (l1 l2) vanishes at the natural width l2 = l1^(-1/2),
// where the wrinkled w is eq. 2.11 with that width; it is the same there in value and
// first derivatives (the energy is C1; its second derivatives jump), and it and its
// derivative vanish at L1 = 1. A wrinkled element carries the uniaxial tension
// T1 = Gs (L1 - 1 / sqrt(L1)) / J along its stretched direction, J = l1 l2 its mean
// dilatation, and none across it. docs/method.md derives this. With
// membrane.wrinkling_residual = r > 0 the element keeps a fraction r of eq. 2.11 where it
// is not taut, w = (1 - r) w_relaxed + r w_s (residual_element).
#include "membrane/neo_hookean.hpp"

namespace capsim {

enum class TensionState { taut, wrinkled, slack };

CAPSIM_HD TensionState tension_state(const SquaredStretches& s) {
  if (s.l1sq <= 1.0)
    return TensionState::slack;
  return s.l1sq * s.l2sq * s.l2sq >= 1.0 ? TensionState::taut : TensionState::wrinkled;
}

// The wrinkled element: W = (Gs A0 / 2) f(L1), f = L1 + 2 L1^(-1/2) - 3, so
// dW = (Gs A0 / 2) f'(L1) dL1.
// From (L1 - L2) dL1 = L1 d i1 - d J^2 (which the two invariants' derivatives
// d i1 = dL1 + dL2, d J^2 = L2 dL1 + L1 dL2 give):
//   dL1/de_a = (L1 d i1/de_a - d J^2/de_a) / (L1 - L2).
// The gap L1 - L2 exceeds L1 - L1^(-1/2) > 0 where the element is wrinkled (no
// isotropic state is: l1 = l2 >= 1 is taut, < 1 slack), so f'(L1) / (L1 - L2) stays
// below f'(L1) / (L1 - L1^(-1/2)) = 1 / L1 even as both vanish at L1 -> 1, and the
// force tends to zero at the slack border; a gap of exactly zero (L1 within round-off
// of 1) is that limit.
CAPSIM_HD double wrinkled_element(const ElementReference& ref, double gs,
                                  const SquaredStretches& s, Vec3 e1, Vec3 e2, double g11,
                                  double g12, double g22, Vec3 grad[3]) {
  const double c = 0.5 * gs * ref.area0;
  const double inv_root = 1.0 / std::sqrt(s.l1sq); // L1^(-1/2)
  const double energy = c * (s.l1sq + 2.0 * inv_root - 3.0);
  if (!(s.gap > 0))
    return energy;
  const double k = c * (1.0 - inv_root * inv_root * inv_root) / s.gap; // ~ f' / (L1 - L2)
  // d i1/de_a as in neo_hookean_element; d J^2/de_a = (d det g/de_a) / det G.
  const Vec3 di1_de1 = 2.0 * (ref.ginv11 * e1 + ref.ginv12 * e2);
  const Vec3 di1_de2 = 2.0 * (ref.ginv12 * e1 + ref.ginv22 * e2);
  const Vec3 dj2_de1 = (2.0 / ref.det_g0) * (g22 * e1 - g12 * e2);
  const Vec3 dj2_de2 = (2.0 / ref.det_g0) * (g11 * e2 - g12 * e1);
  const Vec3 f1 = k * (s.l1sq * di1_de1 - dj2_de1);
  const Vec3 f2 = k * (s.l1sq * di1_de2 - dj2_de2);
  grad[0] -= f1 + f2;
  grad[1] += f1;
  grad[2] += f2;
  return energy;
}

// Returns the relaxed element energy A0 w and adds its exact gradient dW/dx_k to grad[k].
CAPSIM_HD double tension_field_element(const ElementReference& ref, double gs, Vec3 x0,
                                       Vec3 x1, Vec3 x2, Vec3 grad[3]) {
  const Vec3 e1 = x1 - x0, e2 = x2 - x0;
  const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
  const SquaredStretches s = squared_stretches(ref, g11, g12, g22);
  switch (tension_state(s)) {
  case TensionState::taut:
    return neo_hookean_element(ref, gs, x0, x1, x2, grad);
  case TensionState::wrinkled:
    return wrinkled_element(ref, gs, s, e1, e2, g11, g12, g22, grad);
  case TensionState::slack:
    break;
  }
  return 0.0;
}

// The principal tensions the relaxed element carries where it is not taut (over Gs):
// T1 = (L1 - L1^(-1/2)) / J, T2 = 0 where wrinkled (the derivative of the wrinkled w
// with respect to l1, over the mean width l2); none where slack.
CAPSIM_HD ElementTensions relaxed_tensions(const SquaredStretches& s,
                                           TensionState state) {
  ElementTensions t;
  t.dilatation = std::sqrt(s.j2);
  if (state == TensionState::wrinkled)
    t.t1 = (s.l1sq - 1.0 / std::sqrt(s.l1sq)) / t.dilatation;
  return t;
}

// The principal tensions the relaxed element carries (over Gs): eq. 2.10 where taut,
// relaxed_tensions elsewhere.
CAPSIM_HD ElementTensions tension_field_tensions(const ElementReference& ref, Vec3 x0,
                                                 Vec3 x1, Vec3 x2) {
  const Vec3 e1 = x1 - x0, e2 = x2 - x0;
  const SquaredStretches s =
      squared_stretches(ref, dot(e1, e1), dot(e1, e2), dot(e2, e2));
  const TensionState state = tension_state(s);
  if (state == TensionState::taut)
    return neo_hookean_tensions(ref, x0, x1, x2);
  return relaxed_tensions(s, state);
}

// The membrane's constitutive law, keys membrane.wrinkling and
// membrane.wrinkling_residual: eq. 2.11 without wrinkling; with it the relaxed energy
// with a residual fraction r of eq. 2.11 (residual_element below). Passed by value to
// the CUDA kernels as well.
struct MembraneLaw {
  bool wrinkling = false; // the relaxed (tension-field) energy instead of eq. 2.11
  double residual = 0;    // r in [0, 1]: the fraction of eq. 2.11 kept (wrinkling only)
};

// The relaxed element with a residual stiffness (Jarasjarungkiat, Wuechner & Bletzinger
// 2008, docs/method.md): W = (1 - r) W_relaxed + r W_2.11, 0 < r <= 1. A wrinkled element
// of the relaxed energy has no stiffness across its wrinkles and a slack one none at
// all, so nothing keeps them from being crushed; this one keeps the fraction r of eq.
// 2.11's response there, including the 1/J^2 term that resists a collapse of the area.
// Where taut both terms are eq. 2.11, and the element is neo_hookean_element itself; the
// gradient is the same combination. r = 1 is eq. 2.11 exactly.
CAPSIM_HD double residual_element(const ElementReference& ref, double gs, double r,
                                  Vec3 x0, Vec3 x1, Vec3 x2, Vec3 grad[3]) {
  const Vec3 e1 = x1 - x0, e2 = x2 - x0;
  const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
  const SquaredStretches s = squared_stretches(ref, g11, g12, g22);
  const TensionState state = tension_state(s);
  if (state == TensionState::taut)
    return neo_hookean_element(ref, gs, x0, x1, x2, grad);
  Vec3 relaxed[3], neo[3];
  const double w_relaxed =
      state == TensionState::wrinkled
          ? wrinkled_element(ref, gs, s, e1, e2, g11, g12, g22, relaxed)
          : 0.0;
  const double w_neo = neo_hookean_element(ref, gs, x0, x1, x2, neo);
  for (int k = 0; k < 3; ++k)
    grad[k] += (1.0 - r) * relaxed[k] + r * neo[k];
  return (1.0 - r) * w_relaxed + r * w_neo;
}

// Its principal tensions (over Gs). The tension of an isotropic energy w(l1, l2) is
// coaxial with the principal stretches, T_a = (1 / l_b) dw/dl_a along the direction of
// l_a; W_2.11 and W_relaxed are both such functions of the same stretches, each with
// T1 along l1 (T1 - T2 = Gs (L1 - L2) / J for eq. 2.10; T1 >= 0 = T2 relaxed), and T is
// linear in w. So the principal directions of the two coincide and the principal
// tensions of W are T_a = (1 - r) T_a,relaxed + r T_a,2.11, still T1 >= T2, with
// T2 >= r T2_2.11: compressive by the residual fraction only.
CAPSIM_HD ElementTensions residual_tensions(const ElementReference& ref, double r,
                                            Vec3 x0, Vec3 x1, Vec3 x2) {
  const Vec3 e1 = x1 - x0, e2 = x2 - x0;
  const SquaredStretches s =
      squared_stretches(ref, dot(e1, e1), dot(e1, e2), dot(e2, e2));
  const TensionState state = tension_state(s);
  const ElementTensions neo = neo_hookean_tensions(ref, x0, x1, x2);
  if (state == TensionState::taut)
    return neo;
  const ElementTensions relaxed = relaxed_tensions(s, state);
  ElementTensions t = neo; // the same dilatation
  t.t1 = (1.0 - r) * relaxed.t1 + r * neo.t1;
  t.t2 = (1.0 - r) * relaxed.t2 + r * neo.t2;
  return t;
}

// The element of the run's membrane: eq. 2.11, or its relaxation with wrinkling, with
// the residual fraction of eq. 2.11 when one is given (r = 0 never evaluates eq. 2.11
// where not taut: the pure relaxed element). The CPU assembly and the CUDA kernel both
// call this one function.
CAPSIM_HD double membrane_element(const ElementReference& ref, double gs, MembraneLaw law,
                                  Vec3 x0, Vec3 x1, Vec3 x2, Vec3 grad[3]) {
  if (!law.wrinkling)
    return neo_hookean_element(ref, gs, x0, x1, x2, grad);
  return law.residual > 0 ? residual_element(ref, gs, law.residual, x0, x1, x2, grad)
                          : tension_field_element(ref, gs, x0, x1, x2, grad);
}

CAPSIM_HD ElementTensions membrane_tensions(const ElementReference& ref, MembraneLaw law,
                                            Vec3 x0, Vec3 x1, Vec3 x2) {
  if (!law.wrinkling)
    return neo_hookean_tensions(ref, x0, x1, x2);
  return law.residual > 0 ? residual_tensions(ref, law.residual, x0, x1, x2)
                          : tension_field_tensions(ref, x0, x1, x2);
}

} // namespace capsim
