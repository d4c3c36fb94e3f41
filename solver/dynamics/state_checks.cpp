#include "dynamics/state_checks.hpp"

#include "mesh/surface_geometry.hpp"

#include <cmath>
#include <sstream>

namespace capsim {

StateFault find_fault(const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
                      double max_extent) {
  const int nn = topo.num_nodes;
  for (int c = 0; c < num_capsules; ++c) {
    const Vec3* xc = &x[c * nn];
    for (int i = 0; i < nn; ++i)
      if (!std::isfinite(xc[i].x) || !std::isfinite(xc[i].y) || !std::isfinite(xc[i].z))
        return {c, -1, "a node position is not finite (NaN or Inf)"};
    Vec3 centre = volume_centroid(topo, xc);
    for (int i = 0; i < nn; ++i)
      if (norm(xc[i] - centre) > max_extent)
        return {c, -1, "the membrane has blown up"};
    // A folded-over triangle points against the averaged normals of its own nodes.
    std::vector<Vec3> n = node_normals(topo, xc);
    for (size_t e = 0; e < topo.triangles.size(); ++e) {
      const auto& t = topo.triangles[e];
      Vec3 an = area_vector2(xc[t[0]], xc[t[1]], xc[t[2]]);
      if (dot(an, n[t[0]] + n[t[1]] + n[t[2]]) <= 0)
        return {c, int(e), "a surface triangle has inverted"};
    }
  }
  return {};
}

std::string broken_state(const Topology& topo, int num_capsules,
                         const std::vector<Vec3>& x, double max_extent) {
  const StateFault f = find_fault(topo, num_capsules, x, max_extent);
  return f.capsule < 0 ? "" : "in capsule " + std::to_string(f.capsule) + ": " + f.what;
}

void require_finite(const std::vector<Vec3>& v, int nodes_per_capsule,
                    const std::string& what, double time) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i].x) || !std::isfinite(v[i].y) || !std::isfinite(v[i].z)) {
      std::ostringstream s;
      s << "numerical failure at gammadot*t = " << time << " in capsule "
        << i / nodes_per_capsule << ": the " << what << " at node "
        << i % nodes_per_capsule
        << " is not finite (NaN or Inf), so the flow cannot be evaluated (the output "
           "folder keeps the last good checkpoint and time series)";
      throw SimulationError(s.str());
    }
}

} // namespace capsim
