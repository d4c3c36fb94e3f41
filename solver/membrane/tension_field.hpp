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
// dilatation, and none across it. docs/method.md derives this.
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

// The principal tensions the relaxed element carries (over Gs): eq. 2.10 where taut;
// T1 = (L1 - L1^(-1/2)) / J, T2 = 0 where wrinkled (the derivative of the wrinkled w
// with respect to l1, over the mean width l2); none where slack.
CAPSIM_HD ElementTensions tension_field_tensions(const ElementReference& ref, Vec3 x0,
                                                 Vec3 x1, Vec3 x2) {
  const Vec3 e1 = x1 - x0, e2 = x2 - x0;
  const SquaredStretches s =
      squared_stretches(ref, dot(e1, e1), dot(e1, e2), dot(e2, e2));
  const TensionState state = tension_state(s);
  if (state == TensionState::taut)
    return neo_hookean_tensions(ref, x0, x1, x2);
  ElementTensions t;
  t.dilatation = std::sqrt(s.j2);
  if (state == TensionState::wrinkled)
    t.t1 = (s.l1sq - 1.0 / std::sqrt(s.l1sq)) / t.dilatation;
  return t;
}

// The element of the run's membrane: eq. 2.11, or its relaxation with wrinkling. The CPU
// assembly and the CUDA kernel both call this one function.
CAPSIM_HD double membrane_element(const ElementReference& ref, double gs, bool wrinkling,
                                  Vec3 x0, Vec3 x1, Vec3 x2, Vec3 grad[3]) {
  return wrinkling ? tension_field_element(ref, gs, x0, x1, x2, grad)
                   : neo_hookean_element(ref, gs, x0, x1, x2, grad);
}

CAPSIM_HD ElementTensions membrane_tensions(const ElementReference& ref, bool wrinkling,
                                            Vec3 x0, Vec3 x1, Vec3 x2) {
  return wrinkling ? tension_field_tensions(ref, x0, x1, x2)
                   : neo_hookean_tensions(ref, x0, x1, x2);
}

} // namespace capsim
