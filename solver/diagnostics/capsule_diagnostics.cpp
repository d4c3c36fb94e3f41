#include "diagnostics/capsule_diagnostics.hpp"

#include "common/constants.hpp"
#include "mesh/surface_geometry.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace capsim {

InPlanePrincipal principal_xy(const Mat3& m) {
  double a = m.m[0][0], b = 0.5 * (m.m[0][1] + m.m[1][0]), c = m.m[1][1];
  double mean = 0.5 * (a + c), radius = std::hypot(0.5 * (a - c), b);
  double angle = 0.5 * std::atan2(2.0 * b, a - c) * 180.0 / kPi; // (-90, 90]
  return {mean + radius, mean - radius, angle};
}

TaylorDeformation taylor_deformation(const Mat3& mo) {
  InPlanePrincipal p = principal_xy(mo);
  double l1 = std::sqrt(p.major), l2 = std::sqrt(std::max(p.minor, 0.0));
  return {(l1 - l2) / (l1 + l2), p.angle_deg};
}

Mat3 stresslet(const Vec3* x, const Vec3* grad, int n, Vec3 centroid) {
  Mat3 s;
  for (int a = 0; a < n; ++a) {
    Vec3 r = x[a] - centroid;
    double rv[3] = {r.x, r.y, r.z}, fv[3] = {grad[a].x, grad[a].y, grad[a].z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        s.m[i][j] += 0.5 * (rv[i] * fv[j] + fv[i] * rv[j]);
  }
  return s;
}

Mat3 viscosity_ratio_stresslet(const Topology& topo, const Vec3* x, const Vec3* u,
                               double lambda) {
  const std::vector<Vec3> nu = node_area_vectors(topo, x);
  Mat3 s;
  for (int a = 0; a < topo.num_nodes; ++a) {
    const double uv[3] = {u[a].x, u[a].y, u[a].z}, nv[3] = {nu[a].x, nu[a].y, nu[a].z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        s.m[i][j] += (lambda - 1) * (uv[i] * nv[j] + nv[i] * uv[j]) / 6;
  }
  return s;
}

CapsuleSample capsule_sample(const Topology& topo, const Vec3* x, const Vec3* grad,
                             double energy, double volume0, double ca, const Vec3* u,
                             double lambda) {
  CapsuleSample c;
  c.centroid = volume_centroid(topo, x);
  TaylorDeformation td = taylor_deformation(second_moment(topo, x, c.centroid));
  c.taylor_D = td.D;
  c.theta_D_deg = td.theta_deg;
  c.stresslet = stresslet(x, grad, topo.num_nodes, c.centroid);
  if (lambda != 1) { // lambda = 1: the traction's part alone, as before
    if (!u)
      throw std::invalid_argument("capsule_sample: lambda != 1 needs the velocity");
    const Mat3 v = viscosity_ratio_stresslet(topo, x, u, lambda);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        c.stresslet.m[i][j] += v.m[i][j];
  }
  for (auto& row : c.stresslet.m)
    for (double& v : row)
      v *= ca;
  InPlanePrincipal ps = principal_xy(c.stresslet);
  c.principal_diff = ps.major - ps.minor;
  c.theta_S_deg = ps.angle_deg;
  c.energy = energy * ca;
  c.volume_error = (enclosed_volume(topo, x) - volume0) / volume0;
  return c;
}

} // namespace capsim
