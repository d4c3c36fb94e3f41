#pragma once
// Single-layer integrals over one flat P1 triangle carrying a linear traction q:
//   I(x) = int_T J(x - y) q(y) dA(y)      (J as in stokeslet.hpp, no 1/(8 pi) factor)
// for a regular target (Gauss rule), a target at one of the triangle's vertices
// (singular: polar/Duffy coordinates centred at the vertex, Pozrikidis), and a target
// close to the triangle (near-singular: adaptive subdivision). All host-device, for the
// CUDA backend.
#include "common/vec3.hpp"
#include "mesh/surface_geometry.hpp"
#include "stokes/kernels/stokeslet.hpp"
#include "stokes/quadrature/triangle_rules.hpp"

namespace capsim {

struct TriangleLoad {
  Vec3 p[3]; // vertices
  Vec3 q[3]; // traction at the vertices
};

CAPSIM_HD Vec3 barycentric(const Vec3 v[3], double l1, double l2) {
  return (1.0 - l1 - l2) * v[0] + l1 * v[1] + l2 * v[2];
}

CAPSIM_HD double triangle_diameter(const Vec3 p[3]) {
  double a = dot(p[1] - p[0], p[1] - p[0]), b = dot(p[2] - p[1], p[2] - p[1]),
         c = dot(p[0] - p[2], p[0] - p[2]);
  return std::sqrt(a > b ? (a > c ? a : c) : (b > c ? b : c));
}

CAPSIM_HD Vec3 triangle_centroid(const Vec3 p[3]) {
  return (1.0 / 3.0) * (p[0] + p[1] + p[2]);
}

// The single-layer integrals below are sums of J(r) w over quadrature points, with r = x
// - y and w the load times the weight and area (the kernel is linear in the load). Each
// rule is written once as a visitor of its (r, w) pairs: integrate_* sum J(r) w point by
// point (as the device kernels do), and the CPU sums collect the pairs of many triangles
// into one vectorised loop (stokes/ewald/pair_buffer.hpp).

// The points of a triangle rule: visit(x - y_g, w_g A q(y_g)), A the triangle's area.
template <class Visit>
CAPSIM_HD void for_each_rule_point(Vec3 x, const TriangleLoad& t, TriangleRule rule,
                                   double area, Visit visit) {
  for (int g = 0; g < rule.n; ++g) {
    const Vec3 y = barycentric(t.p, rule.l1[g], rule.l2[g]);
    const Vec3 q = barycentric(t.q, rule.l1[g], rule.l2[g]);
    visit(x - y, (rule.w[g] * area) * q);
  }
}

template <class Visit>
CAPSIM_HD void for_each_rule_point(Vec3 x, const TriangleLoad& t, TriangleRule rule,
                                   Visit visit) {
  for_each_rule_point(x, t, rule, 0.5 * norm(area_vector2(t.p[0], t.p[1], t.p[2])),
                      visit);
}

// Target at vertex k. With y = p_k + s d(t), d(t) = (1-t)(p_k1 - p_k) + t(p_k2 - p_k) and
// dA = 2A s ds dt, J(s d) = J(d)/s cancels the Jacobian's s, and q is linear in s, so the
// s-integral is exact: I = 2A int_0^1 J(d(t)) (q_k + (q(t) - q_k)/2) dt, with q(t) the
// load on the opposite edge. Only t needs quadrature: n-point Gauss-Legendre (gl_x,
// gl_w), visited as (d(t_g), 2A w_g (q_k + q(t_g))/2).
template <class Visit>
CAPSIM_HD void for_each_singular_vertex_point(int k, const TriangleLoad& t,
                                              const double* gl_x, const double* gl_w,
                                              int n, Visit visit) {
  const Vec3 p0 = t.p[k], p1 = t.p[(k + 1) % 3], p2 = t.p[(k + 2) % 3];
  const Vec3 q0 = t.q[k], q1 = t.q[(k + 1) % 3], q2 = t.q[(k + 2) % 3];
  const double two_area = norm(area_vector2(p0, p1, p2));
  for (int g = 0; g < n; ++g) {
    const double s = gl_x[g];
    const Vec3 d = (1.0 - s) * (p1 - p0) + s * (p2 - p0);
    const Vec3 qe = (1.0 - s) * q1 + s * q2;
    visit(d, (0.5 * two_area * gl_w[g]) * (q0 + qe));
  }
}

// Target near (not on) the triangle: split 1-to-4 until every piece is at least
// near_ratio diameters away from x (or max_depth is reached), then apply the 7-point
// rule. An explicit stack instead of recursion keeps it usable in device code. Midpoint
// subdivision halves the diameter and quarters the area of every piece exactly, so both
// are computed once, and distances are compared squared.
template <class Visit>
CAPSIM_HD void for_each_adaptive_point(Vec3 x, const TriangleLoad& t, double near_ratio,
                                       int max_depth, Visit visit) {
  constexpr int kStack = 64; // 3 * depth + 1 entries suffice; depth is capped below
  // Uninitialised slots: an array of TriangleLoad would be zeroed (Vec3's initialisers),
  // 9 kB per call, which cost more than the quadrature itself.
  union Slot {
    TriangleLoad load;
    CAPSIM_HD Slot() {}
  };
  Slot stack[kStack];
  int depth[kStack];
  int top = 0;
  stack[0].load = t;
  depth[0] = 0;
  if (max_depth > 20)
    max_depth = 20;
  const TriangleRule rule7 = triangle_rule_7();
  const double reach0 = near_ratio * triangle_diameter(t.p);
  const double area0 = 0.5 * norm(area_vector2(t.p[0], t.p[1], t.p[2]));
  while (top >= 0) {
    const TriangleLoad cur = stack[top].load;
    const int d = depth[top--];
    const double scale = 1.0 / double(1 << d), reach = reach0 * scale;
    const Vec3 c = x - triangle_centroid(cur.p);
    if (d >= max_depth || dot(c, c) >= reach * reach) {
      for_each_rule_point(x, cur, rule7, area0 * scale * scale, visit);
      continue;
    }
    Vec3 mp[3] = {0.5 * (cur.p[0] + cur.p[1]), 0.5 * (cur.p[1] + cur.p[2]),
                  0.5 * (cur.p[2] + cur.p[0])};
    Vec3 mq[3] = {0.5 * (cur.q[0] + cur.q[1]), 0.5 * (cur.q[1] + cur.q[2]),
                  0.5 * (cur.q[2] + cur.q[0])};
    TriangleLoad kids[4] = {{{cur.p[0], mp[0], mp[2]}, {cur.q[0], mq[0], mq[2]}},
                            {{mp[0], cur.p[1], mp[1]}, {mq[0], cur.q[1], mq[1]}},
                            {{mp[2], mp[1], cur.p[2]}, {mq[2], mq[1], cur.q[2]}},
                            {{mp[0], mp[1], mp[2]}, {mq[0], mq[1], mq[2]}}};
    for (const auto& kid : kids) {
      stack[++top].load = kid;
      depth[top] = d + 1;
    }
  }
}

// The sum of J(r) w over the points of a visitor above.
template <class ForEachPoint> CAPSIM_HD Vec3 stokeslet_sum_of(ForEachPoint points) {
  Vec3 sum;
  points([&](Vec3 r, Vec3 w) { sum += stokeslet_apply(r, w); });
  return sum;
}

// Gauss rule on the whole triangle; accurate when x is far compared with the diameter.
CAPSIM_HD Vec3 integrate_regular(Vec3 x, const TriangleLoad& t, TriangleRule rule) {
  return stokeslet_sum_of([&](auto visit) { for_each_rule_point(x, t, rule, visit); });
}

CAPSIM_HD Vec3 integrate_singular_vertex(int k, const TriangleLoad& t, const double* gl_x,
                                         const double* gl_w, int n) {
  return stokeslet_sum_of(
      [&](auto visit) { for_each_singular_vertex_point(k, t, gl_x, gl_w, n, visit); });
}

CAPSIM_HD Vec3 integrate_adaptive(Vec3 x, const TriangleLoad& t, double near_ratio,
                                  int max_depth) {
  return stokeslet_sum_of(
      [&](auto visit) { for_each_adaptive_point(x, t, near_ratio, max_depth, visit); });
}

} // namespace capsim
