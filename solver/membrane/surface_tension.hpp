#pragma once
// A drop's interface (membrane.law: drop): an isotropic tension sigma with the energy
// W = sigma A, A the area of the deformed surface; it has no reference state. Its exact
// gradient on a P1 triangle is the discrete form of the Young-Laplace traction jump
// 2 sigma H n (the mean-curvature normal of the polyhedron, Pozrikidis 2001, J. Comput.
// Phys. 169, 250, on curvature from the area's variation), so a drop shares the
// membrane's whole load path (nodal forces dW/dx, q = F / A_node, the stresslet of
// capsule_diagnostics.hpp).
#include "common/vec3.hpp"

namespace capsim {

// Returns the element energy sigma A_e and adds its gradient dW/dx_k to grad[k]:
// dA_e/dx_k = n_hat x (x_{k+2} - x_{k+1}) / 2, n_hat the unit normal (x1-x0) x (x2-x0).
CAPSIM_HD double surface_tension_element(double sigma, Vec3 x0, Vec3 x1, Vec3 x2,
                                         Vec3 grad[3]) {
  const Vec3 an = cross(x1 - x0, x2 - x0); // twice the area along the normal
  const double twice_area = norm(an);
  const Vec3 n_hat = (1.0 / twice_area) * an;
  const Vec3 x[3] = {x0, x1, x2};
  for (int k = 0; k < 3; ++k)
    grad[k] += (0.5 * sigma) * cross(n_hat, x[(k + 2) % 3] - x[(k + 1) % 3]);
  return 0.5 * sigma * twice_area;
}

} // namespace capsim
