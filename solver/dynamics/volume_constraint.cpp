#include "dynamics/volume_constraint.hpp"

#include "mesh/surface_geometry.hpp"

#include <cmath>

namespace capsim {

std::vector<double> enforce_volume(const Topology& topo, int num_capsules,
                                   std::vector<Vec3>& x,
                                   const std::vector<double>& volume0) {
  const int nn = topo.num_nodes;
  std::vector<double> drift(num_capsules);
  for (int c = 0; c < num_capsules; ++c) {
    Vec3* xc = &x[c * nn];
    for (int pass = 0; pass < 8; ++pass) {
      double v = enclosed_volume(topo, xc);
      double err = (v - volume0[c]) / volume0[c];
      if (pass == 0)
        drift[c] = err;
      if (std::abs(err) < 1e-13)
        break;
      double shift = (volume0[c] - v) / surface_area(topo, xc);
      std::vector<Vec3> n = node_normals(topo, xc);
      for (int i = 0; i < nn; ++i)
        xc[i] += shift * n[i];
    }
  }
  return drift;
}

void remove_volume_rate(const Topology& topo, int num_capsules,
                        const std::vector<Vec3>& x, std::vector<Vec3>& u) {
  const int nn = topo.num_nodes;
  for (int c = 0; c < num_capsules; ++c) {
    const Vec3* xc = &x[c * nn];
    Vec3* uc = &u[c * nn];
    const std::vector<Vec3> g = node_area_vectors(topo, xc); // 6 dV/dx_i
    double rate = 0, along_normals = 0;
    for (int i = 0; i < nn; ++i) {
      rate += dot(g[i], uc[i]);
      along_normals += norm(g[i]);
    }
    const double r = rate / along_normals;
    for (int i = 0; i < nn; ++i)
      uc[i] -= (r / norm(g[i])) * g[i];
  }
}

} // namespace capsim
