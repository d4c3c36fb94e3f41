#include "dynamics/normal_motion.hpp"

#include "mesh/surface_geometry.hpp"

namespace capsim {

void keep_normal_motion(const Topology& topo, int num_capsules,
                        const std::vector<Vec3>& x, std::vector<Vec3>& u) {
  const int nn = topo.num_nodes;
  for (int c = 0; c < num_capsules; ++c) {
    const Vec3* xc = &x[c * nn];
    Vec3* uc = &u[c * nn];
    const std::vector<double> area = node_areas(topo, xc);
    const std::vector<Vec3> g = node_area_vectors(topo, xc);
    Vec3 mean{};
    double total = 0;
    for (int i = 0; i < nn; ++i) {
      mean += area[i] * uc[i];
      total += area[i];
    }
    mean = (1.0 / total) * mean;
    for (int i = 0; i < nn; ++i) {
      const Vec3 n = (1.0 / norm(g[i])) * g[i];
      uc[i] = mean + dot(uc[i] - mean, n) * n;
    }
  }
}

} // namespace capsim
