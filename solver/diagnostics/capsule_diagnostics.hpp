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

// The stresslet's part from a viscosity ratio lambda != 1 (Batchelor 1970, J. Fluid Mech.
// 41, 545, the particle stress int [x sigma.n - mu (u n + n u)] dA over the surface, with
// sigma the outer stress): writing sigma_out.n = sigma_in.n + q and int x sigma_in.n dA =
// int_V sigma_in dV = lambda mu int (u n + n u) dA + isotropic (the divergence theorem
// inside; a capsule's surface moves with both fluids), the stresslet is
//   S = int 1/2 (x q + q x) dA + (lambda - 1) mu int (u n + n u) dA,
// the (lambda - 1) term being Batchelor's -mu (1 - lambda) int (u n + n u) dA (also
// Rallison 1984, Annu. Rev. Fluid Mech. 16, 45, eq. for a drop's stresslet). Returned
// here in mu = 1 units: (lambda - 1) sum_i (u_i nu_i + nu_i u_i) / 6, nu_i the node area
// vectors (6 dV/dx_i, surface_geometry.hpp), the exact integral of P1 velocity on the
// flat triangles.
Mat3 viscosity_ratio_stresslet(const Topology& topo, const Vec3* x, const Vec3* u,
                               double lambda);

// Everything written per capsule and sample. grad is dW/dx with W computed for Gs = 1/Ca,
// so stresslet and energy are multiplied by Ca to be in units of Gs a^2. With lambda != 1
// the node velocities u (in gammadot a) add viscosity_ratio_stresslet; at lambda = 1 u is
// not read (may be null).
CapsuleSample capsule_sample(const Topology& topo, const Vec3* x, const Vec3* grad,
                             double energy, double volume0, double ca,
                             const Vec3* u = nullptr, double lambda = 1.0);

} // namespace capsim
