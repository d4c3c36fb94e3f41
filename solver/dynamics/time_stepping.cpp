#include "dynamics/time_stepping.hpp"

#include "membrane/compression.hpp"
#include "mesh/surface_geometry.hpp"

#include <cmath>
#include <iomanip>
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

namespace {

const char* const kStepAdvice =
    ". The time step is probably too large for this Ca and mesh: start again with a "
    "smaller dt or dt_safety (the output folder keeps the last good checkpoint and time "
    "series)";

std::string tension_text(double t) {
  std::ostringstream s;
  s << std::setprecision(2) << t << " Gs";
  return s.str();
}

// What an inverted triangle says of its cause: with compressed elements next to it the
// membrane buckled (docs/suspensions.md: halving dt moved no such fold); otherwise the
// step was too large.
std::string inversion_cause(const Membrane& membrane, const Vec3* xc, int triangle) {
  const std::vector<ElementTensions> t = membrane.neo_hookean_element_tensions(xc);
  const Compression all = compression(t);
  const Compression near = compression_near(membrane.topology(), t, triangle);
  if (all.elements == 0)
    return kStepAdvice;
  std::ostringstream s;
  // A relaxed membrane carries no compression: the paper's energy's T2 then says where
  // it wrinkles and how far the elements there are squeezed, not a tension it carries.
  s << "; " << all.elements << " of its " << all.of << " elements are in compression"
    << (membrane.wrinkling() ? " under the paper's energy, which the relaxed membrane "
                               "does not carry"
                             : "")
    << " (T2 < " << kCompressedTension << " Gs)";
  if (near.elements == 0)
    return s.str() + ", down to T2 = " + tension_text(all.min_tension) +
           ", none next to the inverted one" + kStepAdvice;
  s << ", down to T2 = " << tension_text(near.min_tension)
    << " next to the inverted one: the membrane buckles under compressive tension, "
       "which nothing resists at the element scale without bending stiffness, and "
       "which a smaller dt did not cure in the measured cases ("
    << (membrane.wrinkling() ? "membrane.wrinkling is on, so the membrane wrinkles "
                               "there; membrane.bending regularises the fold"
                             : "membrane.wrinkling or membrane.bending regularise it")
    << "; docs/suspensions.md). The output folder keeps the last good checkpoint and "
       "time series";
  return s.str();
}

} // namespace

void check_state(const Membrane& membrane, int num_capsules, const std::vector<Vec3>& x,
                 double time, double max_extent) {
  const Topology& topo = membrane.topology();
  const StateFault f = find_fault(topo, num_capsules, x, max_extent);
  if (f.capsule < 0)
    return;
  std::ostringstream s;
  s << "numerical failure at gammadot*t = " << time << " in capsule " << f.capsule << ": "
    << f.what
    << (f.triangle >= 0
            ? inversion_cause(membrane, &x[f.capsule * topo.num_nodes], f.triangle)
            : kStepAdvice);
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
