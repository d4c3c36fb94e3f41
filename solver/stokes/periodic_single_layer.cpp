#include "stokes/periodic_single_layer.hpp"

#include "stokes/ewald_kernel.hpp"
#include "stokes/ewald_reciprocal.hpp"
#include "stokes/periodic_cells.hpp"
#include "stokes/triangle_sources.hpp"

#include <cmath>
#include <stdexcept>

namespace capsim {
namespace {

// Correction for the image of triangle t nearest to x, if it is near: the accurate
// screened integral minus the far-rule screened sum already counted for it.
Vec3 near_correction(const ShearedLattice& g, Vec3 x, int node, const Topology& topo,
                     int t_global, TriangleLoad load, const EwaldParameters& p,
                     const QuadratureOptions& o, const LineRule& gl) {
  const Vec3 c = triangle_centroid(load.p);
  const Vec3 d = wrap_to_cell(g, x - c);
  const double diam = triangle_diameter(load.p);
  if (norm(d) >= o.far_ratio * diam)
    return {};
  const Vec3 shift = (x - d) - c; // lattice vector to the nearest image
  for (auto& v : load.p)
    v += shift;
  // The singular rule only for the triangle's own image (shift 0) at its own vertex.
  const int vertex = norm(shift) < 1e-9 * g.L ? vertex_index(topo, node, t_global) : -1;
  const auto screened = [&](Vec3 r, Vec3 f) { return ewald_real_apply(r, f, p.xi); };
  const auto smooth = [&](Vec3 r, Vec3 f) {
    return ewald_real_minus_free_apply(r, f, p.xi);
  };
  // Accurate J, plus the bounded J^EI - J by the 7-point rule, minus what the far rule of
  // the screened kernel already counted.
  return accurate_single_layer(x, vertex, load, o, gl) +
         integrate_rule(x, load, triangle_rule_7(), smooth) -
         integrate_rule(x, load, triangle_rule_3(), screened);
}

// sum over the far-rule points within r_cut (all images), through the cell list.
Vec3 real_space_sum_cells(Vec3 x, const FarSources& s, const PeriodicCells& cells,
                          const EwaldParameters& p) {
  Vec3 sum;
  const double rc2 = p.r_cut * p.r_cut;
  cells.for_neighbours(x, [&](int k, Vec3 y) {
    Vec3 r = x - y;
    if (dot(r, r) < rc2)
      sum += ewald_real_apply(r, {s.f[0][k], s.f[1][k], s.f[2][k]}, p.xi);
  });
  return sum;
}

std::vector<Vec3> point_positions(const FarSources& s) {
  std::vector<Vec3> y(s.size());
  for (size_t k = 0; k < s.size(); ++k)
    y[k] = {s.y[0][k], s.y[1][k], s.y[2][k]};
  return y;
}

} // namespace

void periodic_single_layer_velocity(const Topology& topo, int num_capsules,
                                    const std::vector<Vec3>& x,
                                    const std::vector<Vec3>& q,
                                    const ShearedLattice& lattice,
                                    const EwaldParameters& ewald,
                                    const QuadratureOptions& quad, std::vector<Vec3>& u,
                                    SpectralEwald* spectral) {
  const int num_tri = int(topo.triangles.size()) * num_capsules;
  std::vector<TriangleLoad> loads(num_tri);
  std::vector<Vec3> centroids(num_tri);
  double max_diam = 0;
  for (int t = 0; t < num_tri; ++t) {
    loads[t] = triangle_load(topo, x, q, t);
    centroids[t] = triangle_centroid(loads[t].p);
    max_diam = std::max(max_diam, triangle_diameter(loads[t].p));
  }
  const FarSources far = far_sources(loads);
  const PeriodicCells point_cells(lattice, ewald.r_cut, point_positions(far));
  const PeriodicCells triangle_cells(lattice, quad.far_ratio * max_diam, centroids);
  const LineRule gl = gauss_legendre_01(quad.singular_points);
  const int n = int(x.size());
  u.assign(n, Vec3{});
#pragma omp parallel for schedule(dynamic, 8)
  for (int i = 0; i < n; ++i) {
    Vec3 sum = real_space_sum_cells(x[i], far, point_cells, ewald);
    triangle_cells.for_neighbours(x[i], [&](int t, Vec3) {
      sum += near_correction(lattice, x[i], i, topo, t, loads[t], ewald, quad, gl);
    });
    u[i] = sum;
  }
  if (spectral)
    spectral->add_reciprocal(lattice, far, x, u);
  else
    ewald_reciprocal_direct(lattice, x, far, ewald, u);
  for (auto& v : u)
    v = (-1.0 / (8.0 * kPi)) * v;
}

} // namespace capsim
