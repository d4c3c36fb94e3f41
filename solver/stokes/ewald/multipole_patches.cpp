#include "stokes/ewald/multipole_patches.hpp"

#include "stokes/quadrature/element_integrals.hpp"

#include <stdexcept>

namespace capsim {

std::vector<PatchMoments> patch_moments(const Topology& topo, int mesh_level,
                                        int patch_level, const Vec3* x, const Vec3* q) {
  if (patch_level > mesh_level)
    throw std::invalid_argument("patch level must not exceed the mesh level");
  const int num = patch_level < 0 ? 1 : icosphere_triangles(patch_level);
  auto patch_of = [&](int t) {
    return patch_level < 0 ? 0 : parent_triangle(t, mesh_level, patch_level);
  };
  std::vector<PatchMoments> p(num);
  std::vector<double> area(num, 0.0);
  const int nt = int(topo.triangles.size());
  for (int t = 0; t < nt; ++t) {
    const Triangle& tri = topo.triangles[t];
    double a = 0.5 * norm(area_vector2(x[tri[0]], x[tri[1]], x[tri[2]]));
    area[patch_of(t)] += a;
    p[patch_of(t)].centre += (a / 3.0) * (x[tri[0]] + x[tri[1]] + x[tri[2]]);
  }
  for (int k = 0; k < num; ++k)
    p[k].centre = (1.0 / area[k]) * p[k].centre;
  // Exact P1 integrals: int phi_a phi_b dA = A/12 (1 + delta_ab).
  for (int t = 0; t < nt; ++t) {
    const Triangle& tri = topo.triangles[t];
    PatchMoments& m = p[patch_of(t)];
    double a = 0.5 * norm(area_vector2(x[tri[0]], x[tri[1]], x[tri[2]]));
    for (int i = 0; i < 3; ++i) {
      m.force += (a / 3.0) * q[tri[i]];
      for (int j = 0; j < 3; ++j) {
        double w = a / 12.0 * (i == j ? 2.0 : 1.0);
        const double qa[3] = {q[tri[i]].x, q[tri[i]].y, q[tri[i]].z};
        const Vec3 r = x[tri[j]] - m.centre;
        const double ra[3] = {r.x, r.y, r.z};
        for (int c = 0; c < 3; ++c)
          for (int d = 0; d < 3; ++d)
            m.dipole.m[c][d] += w * qa[c] * ra[d];
      }
    }
  }
  return p;
}

Vec3 patch_velocity(Vec3 x, const std::vector<PatchMoments>& patches) {
  Vec3 v;
  for (const auto& p : patches) {
    Vec3 r = x - p.centre;
    v += stokeslet_apply(r, p.force) - stokeslet_gradient_contract(r, p.dipole);
  }
  return v;
}

Vec3 surface_velocity_at(Vec3 x, const Topology& topo, const Vec3* nodes, const Vec3* q) {
  Vec3 v;
  for (const auto& tri : topo.triangles) {
    TriangleLoad t{{nodes[tri[0]], nodes[tri[1]], nodes[tri[2]]},
                   {q[tri[0]], q[tri[1]], q[tri[2]]}};
    v += integrate_adaptive(x, t, 4.0, 8);
  }
  return v;
}

} // namespace capsim
