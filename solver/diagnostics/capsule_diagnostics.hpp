#pragma once
// Per-capsule diagnostics (docs/conventions.md): Taylor parameter and angle from the
// second moment of the enclosed volume (eq. 4.2), stresslet (eq. 4.4) and its principal
// values in the shear plane (eqs. 4.12-4.15).
#include "io/records.hpp"
#include "mesh/icosphere.hpp"

namespace capsim {

// Eigen-decomposition of the x-y block of a symmetric tensor.
struct InPlanePrincipal {
  double major = 0, minor = 0; // eigenvalues, major >= minor
  double angle_deg = 0;        // angle of the major eigenvector with +x, in (-90, 90]
};
InPlanePrincipal principal_xy(const Mat3& m);

// D = (sqrt m1 - sqrt m2)/(sqrt m1 + sqrt m2) from the x-y block of Mo = int_V r r dV;
// for an ellipsoid this is (L1 - L2)/(L1 + L2) of its in-plane axes.
struct TaylorDeformation {
  double D = 0, theta_deg = 0;
};
TaylorDeformation taylor_deformation(const Mat3& second_moment);

// S = sum_a 1/2 (r_a F_a + F_a r_a), r_a = x_a - centroid, F_a = dW/dx_a. This is
// int 1/2 (r q + q r) dA evaluated in the FEM weak form: exact for the consistent-mass
// load, and the lumped-mass quadrature of the same integral for the lumped one.
Mat3 stresslet(const Vec3* x, const Vec3* grad, int n, Vec3 centroid);

// Everything written per capsule and sample. grad is dW/dx with W computed for Gs = 1/Ca,
// so stresslet and energy are multiplied by Ca to be in units of Gs a^2.
CapsuleSample capsule_sample(const Topology& topo, const Vec3* x, const Vec3* grad,
                             double energy, double volume0, double ca);

} // namespace capsim
