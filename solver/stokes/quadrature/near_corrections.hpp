#pragma once
// The near-field corrections of the single-layer sums, host-device so that the CPU sums
// and the CUDA kernels apply the same quadrature. A far sum counts every triangle by its
// 3-point rule; for a triangle near the target that is replaced by an accurate integral
// (the polar rule when the target is one of its vertices, adaptive subdivision
// otherwise), so the correction is the accurate integral minus the 3-point rule.
#include "stokes/quadrature/element_integrals.hpp"
#include "stokes/cells/sheared_lattice.hpp"

namespace capsim {

// The accurate rules, as plain values and pointers that device code can take.
struct NearRule {
  double far_ratio = 1.5;       // triangles closer than this many diameters are near
  double near_ratio = 1.0;      // subdivide until pieces are this many diameters away
  int max_depth = 6;            // deepest subdivision
  const double* gl_x = nullptr; // Gauss-Legendre nodes of the polar rule on [0, 1]
  const double* gl_w = nullptr; // and its weights
  int gl_n = 0;
};

// The points of int_T J(x - y) q dA (see element_integrals.hpp): the polar rule when x is
// vertex `vertex` (0-2) of t, adaptive subdivision when vertex < 0.
template <class Visit>
CAPSIM_HD void for_each_accurate_point(Vec3 x, int vertex, const TriangleLoad& t,
                                       const NearRule& r, Visit visit) {
  if (vertex >= 0)
    for_each_singular_vertex_point(vertex, t, r.gl_x, r.gl_w, r.gl_n, visit);
  else
    for_each_adaptive_point(x, t, r.near_ratio, r.max_depth, visit);
}

// The points of the free-space correction for a near triangle (the caller decides that
// it is near): the accurate rule's, then the 3-point rule's with the load negated.
template <class Visit>
CAPSIM_HD void for_each_correction_point(Vec3 x, int vertex, const TriangleLoad& t,
                                         const NearRule& r, Visit visit) {
  for_each_accurate_point(x, vertex, t, r, visit);
  for_each_rule_point(x, t, triangle_rule_3(), [&](Vec3 d, Vec3 w) { visit(d, -w); });
}

// Free space: the correction for a near triangle, accurate integral minus 3-point rule.
CAPSIM_HD Vec3 free_near_correction(Vec3 x, int vertex, const TriangleLoad& t,
                                    const NearRule& r) {
  return stokeslet_sum_of(
      [&](auto visit) { for_each_correction_point(x, vertex, t, r, visit); });
}

// Sheared periodic box: the points of the correction for the image of `load` moved by
// the lattice vector `shift`, near x. The real-space and reciprocal Ewald sums together
// apply the 3-point rule to the whole periodic kernel J^E, so the free-space correction
// is the right one for every xi (periodic_single_layer.hpp); the polar rule is used only
// for the triangle's own image (shift exactly 0), at x's vertex `own_vertex` (-1: none).
template <class Visit>
CAPSIM_HD void for_each_image_correction_point(Vec3 x, int own_vertex, TriangleLoad load,
                                               Vec3 shift, const NearRule& r,
                                               Visit visit) {
  const bool own = dot(shift, shift) == 0;
  for (auto& v : load.p)
    v += shift;
  for_each_correction_point(x, own ? own_vertex : -1, load, r, visit);
}

CAPSIM_HD Vec3 image_near_correction(Vec3 x, int own_vertex, const TriangleLoad& load,
                                     Vec3 shift, const NearRule& r) {
  return stokeslet_sum_of([&](auto visit) {
    for_each_image_correction_point(x, own_vertex, load, shift, r, visit);
  });
}

// The same for the image of `load` nearest to x, zero unless that image is near.
CAPSIM_HD Vec3 nearest_image_near_correction(const ShearedLattice& g, Vec3 x,
                                             int own_vertex, const TriangleLoad& load,
                                             const NearRule& r) {
  const Vec3 c = triangle_centroid(load.p);
  const Vec3 d = wrap_to_cell(g, x - c);
  if (norm(d) >= r.far_ratio * triangle_diameter(load.p))
    return {};
  Vec3 shift = (x - d) - c; // the lattice vector to the nearest image
  if (norm(shift) < 1e-9 * g.L)
    shift = Vec3{};
  return image_near_correction(x, own_vertex, load, shift, r);
}

} // namespace capsim
