#pragma once
// Quadrature rules: symmetric Gauss rules on the triangle (barycentric points l1, l2 with
// l0 = 1 - l1 - l2, weights summing to 1) and Gauss-Legendre on [0, 1]. The triangle
// rules are constexpr tables so that host-device kernels can use them.
#include "common/hd.hpp"

#include <vector>

namespace capsim {

struct TriangleRule {
  int n;
  const double* l1;
  const double* l2;
  const double* w;
};

namespace rules {
// 3 interior points, exact for quadratics.
constexpr double r3_l1[3] = {1.0 / 6, 2.0 / 3, 1.0 / 6};
constexpr double r3_l2[3] = {1.0 / 6, 1.0 / 6, 2.0 / 3};
constexpr double r3_w[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
// Radon's 7-point rule, exact for quintics: a = (6 -+ sqrt 15)/21, w = (155 -+ sqrt
// 15)/1200.
constexpr double a1 = 0.101286507323456338800987361915,
                 b1 = 0.797426985353087322398025276170;
constexpr double a2 = 0.470142064105115089770441209513,
                 b2 = 0.059715871789769820459117580974;
constexpr double w1 = 0.125939180544827152595683945500,
                 w2 = 0.132394152788506180737649387833;
constexpr double r7_l1[7] = {1.0 / 3, a1, b1, a1, a2, b2, a2};
constexpr double r7_l2[7] = {1.0 / 3, a1, a1, b1, a2, a2, b2};
constexpr double r7_w[7] = {9.0 / 40, w1, w1, w1, w2, w2, w2};
} // namespace rules

// The far-field rule.
CAPSIM_HD TriangleRule triangle_rule_3() {
  return {3, rules::r3_l1, rules::r3_l2, rules::r3_w};
}
// The near-field rule (leaves of the adaptive subdivision).
CAPSIM_HD TriangleRule triangle_rule_7() {
  return {7, rules::r7_l1, rules::r7_l2, rules::r7_w};
}

struct LineRule {
  std::vector<double> x, w; // nodes in (0, 1), weights summing to 1
};

// n-point Gauss-Legendre rule mapped to [0, 1] (Newton iteration on P_n).
LineRule gauss_legendre_01(int n);

} // namespace capsim
