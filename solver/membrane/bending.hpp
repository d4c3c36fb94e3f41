#pragma once
// Optional bending resistance of the membrane (off by default: the paper's membrane has
// none). A membrane without bending stiffness has nothing that resists a fold shorter
// than the element size; at Ca 0.6 and phi 0.4 the tip of a strongly stretched capsule
// folds that way and a triangle inverts (docs/suspensions.md). A bending modulus damps
// those element-scale modes most (their bending rate grows as 1/h^3), but it also
// stiffens the capsule as a whole: docs/suspensions.md measures by how much.
//
// Discrete-shells hinge energy (Grinspun et al. 2003) measured from the reference sphere:
// each interior edge e with dihedral angle theta_e carries
//   E_e = (kb / 2) w_e (theta_e - theta0_e)^2,   w_e = 3 |e0|^2 / A0_e,
// with theta0_e, |e0| and A0_e (the area of the two triangles) of the reference state.
// The weight makes the sum converge with the mesh: for a change of curvature dk alike in
// every direction it tends to (kb / 2) int (2 dk)^2 dA, the Helfrich energy; in general
// it tends to a quadratic form in the changes of curvature and stretch that is not
// exactly Helfrich's (a stretch of a curved surface turns the hinges too), but is the
// same at every mesh level, so one kb means the same at each
// (tests/cpp/test_bending.cpp). A uniform inflation bends nothing.
#include "common/vec3.hpp"
#include "mesh/icosphere.hpp"

#include <vector>

namespace capsim {

// The two triangles (a, b, c) and (b, a, d) that share the edge a-b, both
// counter-clockwise seen from outside.
struct Hinge {
  int a, b, c, d;
};

struct HingeReference {
  double theta0 = 0; // reference dihedral angle
  double weight = 0; // 3 |e0|^2 / A0
};

// Every edge of a closed mesh, once.
std::vector<Hinge> make_hinges(const Topology& topo);

// The angle from the normal n1 to n2 about the edge e (of length len), signed.
CAPSIM_HD double normal_angle(Vec3 n1, Vec3 n2, Vec3 e, double len) {
  return std::atan2(dot(cross(n1, n2), e) / len, dot(n1, n2));
}

// Signed dihedral angle at the edge a-b: 0 when flat, > 0 where the surface is convex
// (a sphere's hinges are all positive).
CAPSIM_HD double dihedral_angle(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const Vec3 e = b - a;
  return normal_angle(cross(e, c - a), cross(a - b, d - b), e, norm(e));
}

CAPSIM_HD HingeReference make_hinge_reference(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const Vec3 e = b - a;
  const double area = 0.5 * (norm(cross(e, c - a)) + norm(cross(a - b, d - b)));
  return {dihedral_angle(a, b, c, d), 3.0 * dot(e, e) / area};
}

// The dihedral angle theta of the hinge (as dihedral_angle) and its gradient
// dtheta[0..3] with respect to nodes a, b, c, d. Moving c along n1 by delta turns its
// triangle about the edge by delta |e| / |n1|, which flattens a convex hinge; a and b
// share the rest so that the four gradients sum to zero (translation) (Bridson et al.
// 2003).
CAPSIM_HD double hinge_angle_gradient(Vec3 a, Vec3 b, Vec3 c, Vec3 d, Vec3 dtheta[4]) {
  const Vec3 e = b - a;
  const Vec3 n1 = cross(e, c - a), n2 = cross(a - b, d - b);
  const double len = norm(e);
  const Vec3 m1 = (1.0 / dot(n1, n1)) * n1, m2 = (1.0 / dot(n2, n2)) * n2;
  dtheta[0] = (-dot(c - b, e) / len) * m1 + (-dot(d - b, e) / len) * m2;
  dtheta[1] = (dot(c - a, e) / len) * m1 + (dot(d - a, e) / len) * m2;
  dtheta[2] = -len * m1;
  dtheta[3] = -len * m2;
  return normal_angle(n1, n2, e, len);
}

// Returns the hinge energy E_e and adds dE_e/dx = kb w (theta - theta0) dtheta/dx to
// grad[0..3] (nodes a, b, c, d).
CAPSIM_HD double bending_hinge(const HingeReference& ref, double kb, Vec3 a, Vec3 b,
                               Vec3 c, Vec3 d, Vec3 grad[4]) {
  Vec3 dtheta[4];
  const double turn = hinge_angle_gradient(a, b, c, d, dtheta) - ref.theta0;
  const double k = kb * ref.weight * turn; // dE/dtheta
  for (int i = 0; i < 4; ++i)
    grad[i] += k * dtheta[i];
  return 0.5 * kb * ref.weight * turn * turn;
}

} // namespace capsim
