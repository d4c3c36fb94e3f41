#pragma once
// The near-field corrections of the single-layer sums, host-device so that the CPU sums
// and the CUDA kernels apply the same quadrature. A far sum counts every triangle by its
// 3-point rule; for a triangle near the target that is replaced by an accurate integral
// (the polar rule when the target is one of its vertices, adaptive subdivision
// otherwise), so the correction is the accurate integral minus the 3-point rule.
#include "stokes/element_integrals.hpp"
#include "stokes/ewald_kernel.hpp"
#include "stokes/sheared_lattice.hpp"

namespace capsim {

// The accurate rules, as plain values and pointers that device code can take.
struct NearRule {
  double far_ratio = 2.0;       // triangles closer than this many diameters are near
  double near_ratio = 1.5;      // subdivide until pieces are this many diameters away
  int max_depth = 6;            // deepest subdivision
  const double* gl_x = nullptr; // Gauss-Legendre nodes of the polar rule on [0, 1]
  const double* gl_w = nullptr; // and its weights
  int gl_n = 0;
};

// int_T J(x - y) q dA: the polar rule when x is vertex `vertex` (0-2) of t, adaptive
// subdivision when vertex < 0.
CAPSIM_HD Vec3 integrate_accurate(Vec3 x, int vertex, const TriangleLoad& t,
                                  const NearRule& r) {
  if (vertex >= 0)
    return integrate_singular_vertex(vertex, t, r.gl_x, r.gl_w, r.gl_n);
  return integrate_adaptive(x, t, r.near_ratio, r.max_depth);
}

// Free space: the correction for a near triangle (the caller decides that it is near).
CAPSIM_HD Vec3 free_near_correction(Vec3 x, int vertex, const TriangleLoad& t,
                                    const NearRule& r) {
  return integrate_accurate(x, vertex, t, r) - integrate_regular(x, t, triangle_rule_3());
}

// Sheared periodic box, screened kernel J^EI: the correction for the image of triangle
// `load` nearest to x, zero unless that image is near. `own_vertex` is x's vertex index
// in the triangle (-1 if x is not one of its vertices); the polar rule is used only for
// the triangle's own image. Accurate J, plus the bounded J^EI - J by the 7-point rule,
// minus the screened 3-point rule that the real-space sum already counted.
CAPSIM_HD Vec3 screened_near_correction(const ShearedLattice& g, Vec3 x, int own_vertex,
                                        TriangleLoad load, double xi, const NearRule& r) {
  const Vec3 c = triangle_centroid(load.p);
  const Vec3 d = wrap_to_cell(g, x - c);
  if (norm(d) >= r.far_ratio * triangle_diameter(load.p))
    return {};
  const Vec3 shift = (x - d) - c; // lattice vector to the nearest image
  for (auto& v : load.p)
    v += shift;
  const int vertex = norm(shift) < 1e-9 * g.L ? own_vertex : -1;
  const auto screened = [xi](Vec3 rr, Vec3 f) { return ewald_real_apply(rr, f, xi); };
  const auto smooth = [xi](Vec3 rr, Vec3 f) {
    return ewald_real_minus_free_apply(rr, f, xi);
  };
  return integrate_accurate(x, vertex, load, r) +
         integrate_rule(x, load, triangle_rule_7(), smooth) -
         integrate_rule(x, load, triangle_rule_3(), screened);
}

} // namespace capsim
