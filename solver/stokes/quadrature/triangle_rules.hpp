#pragma once
// Quadrature rules: symmetric Gauss rules on the triangle (barycentric points l1, l2 with
// l0 = 1 - l1 - l2, weights summing to 1) and Gauss-Legendre on [0, 1]. The triangle
// rules are returned by value so that host-device kernels can use them.
#include "common/hd.hpp"

#include <vector>

namespace capsim {

// The rule's tables are held by value (the first n entries are used), so that device code
// gets its own copy: a kernel cannot read a host-side constant array through a pointer.
struct TriangleRule {
  int n;
  double l1[7], l2[7], w[7];
};

namespace rules {
// Radon's 7-point rule, exact for quintics: a = (6 -+ sqrt 15)/21, w = (155 -+ sqrt
// 15)/1200.
constexpr double a1 = 0.101286507323456338800987361915,
                 b1 = 0.797426985353087322398025276170;
constexpr double a2 = 0.470142064105115089770441209513,
                 b2 = 0.059715871789769820459117580974;
constexpr double w1 = 0.125939180544827152595683945500,
                 w2 = 0.132394152788506180737649387833;
} // namespace rules

// The far-field rule: 3 interior points, exact for quadratics.
CAPSIM_HD TriangleRule triangle_rule_3() {
  return {3,
          {1.0 / 6, 2.0 / 3, 1.0 / 6},
          {1.0 / 6, 1.0 / 6, 2.0 / 3},
          {1.0 / 3, 1.0 / 3, 1.0 / 3}};
}
// The near-field rule (leaves of the adaptive subdivision).
CAPSIM_HD TriangleRule triangle_rule_7() {
  using namespace rules;
  return {7,
          {1.0 / 3, a1, b1, a1, a2, b2, a2},
          {1.0 / 3, a1, a1, b1, a2, a2, b2},
          {9.0 / 40, w1, w1, w1, w2, w2, w2}};
}

struct LineRule {
  std::vector<double> x, w; // nodes in (0, 1), weights summing to 1
};

// n-point Gauss-Legendre rule mapped to [0, 1] (Newton iteration on P_n).
LineRule gauss_legendre_01(int n);

} // namespace capsim
