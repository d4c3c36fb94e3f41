#include "dynamics/time_stepping.hpp"

#include "mesh/surface_geometry.hpp"

#include <cmath>
#include <sstream>

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

std::string broken_state(const Topology& topo, int num_capsules,
                         const std::vector<Vec3>& x, double max_extent) {
  const int nn = topo.num_nodes;
  for (int c = 0; c < num_capsules; ++c) {
    const std::string where = "in capsule " + std::to_string(c) + ": ";
    const Vec3* xc = &x[c * nn];
    for (int i = 0; i < nn; ++i)
      if (!std::isfinite(xc[i].x) || !std::isfinite(xc[i].y) || !std::isfinite(xc[i].z))
        return where + "a node position is not finite (NaN or Inf)";
    Vec3 centre = volume_centroid(topo, xc);
    for (int i = 0; i < nn; ++i)
      if (norm(xc[i] - centre) > max_extent)
        return where + "the membrane has blown up";
    // A folded-over triangle points against the averaged normals of its own nodes.
    std::vector<Vec3> n = node_normals(topo, xc);
    for (const auto& t : topo.triangles) {
      Vec3 an = area_vector2(xc[t[0]], xc[t[1]], xc[t[2]]);
      if (dot(an, n[t[0]] + n[t[1]] + n[t[2]]) <= 0)
        return where + "a surface triangle has inverted";
    }
  }
  return "";
}

void check_state(const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
                 double time, double max_extent) {
  const std::string problem = broken_state(topo, num_capsules, x, max_extent);
  if (problem.empty())
    return;
  std::ostringstream s;
  s << "numerical failure at gammadot*t = " << time << " " << problem
    << ". The time step is probably too large for this Ca and mesh: start again "
       "with a smaller dt or dt_safety (the output folder keeps the last good "
       "checkpoint and time series)";
  throw SimulationError(s.str());
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

double automatic_time_step(double ca, double mean_edge, double safety, double bending) {
  return safety * ca * mean_edge / (1 + 4 * bending / (mean_edge * mean_edge));
}

} // namespace capsim
