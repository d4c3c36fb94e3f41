#include "stokes/single_layer/single_layer.hpp"

#include "common/vector_clones.hpp"
#include "stokes/quadrature/element_integrals.hpp"
#include "stokes/quadrature/near_triangles.hpp"
#include "stokes/ewald/pair_buffer.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <cmath>
#include <omp.h>

namespace capsim {
namespace {

// sum_g J(x - y_g) f_g over all far-rule points: the O(N^2) part, written so that the
// compiler vectorises it (no branches, structure-of-arrays).
CAPSIM_VECTOR_CLONES Vec3 far_sum(Vec3 x, const FarSources& s) {
  const size_t n = s.y[0].size();
  const double *yx = s.y[0].data(), *yy = s.y[1].data(), *yz = s.y[2].data();
  const double *fx = s.f[0].data(), *fy = s.f[1].data(), *fz = s.f[2].data();
  double ux = 0, uy = 0, uz = 0;
#pragma omp simd reduction(+ : ux, uy, uz)
  for (size_t g = 0; g < n; ++g) {
    double rx = x.x - yx[g], ry = x.y - yy[g], rz = x.z - yz[g];
    double rinv = 1.0 / std::sqrt(rx * rx + ry * ry + rz * rz);
    double rf = (rx * fx[g] + ry * fy[g] + rz * fz[g]) * rinv * rinv * rinv;
    ux += fx[g] * rinv + rx * rf;
    uy += fy[g] * rinv + ry * rf;
    uz += fz[g] * rinv + rz * rf;
  }
  return {ux, uy, uz};
}

} // namespace

void single_layer_velocity(const Topology& topo, int num_capsules,
                           const std::vector<Vec3>& x, const std::vector<Vec3>& q,
                           const QuadratureOptions& opts, std::vector<Vec3>& u,
                           SingleLayerTimings* timings) {
  const double t0 = omp_get_wtime();
  const int nt = int(topo.triangles.size());
  const int num_tri = nt * num_capsules;
  std::vector<TriangleLoad> loads(num_tri);
  std::vector<Vec3> centroids(num_tri);
  std::vector<double> diameters(num_tri);
  for (int t = 0; t < num_tri; ++t) {
    loads[t] = triangle_load(topo, x, q, t);
    centroids[t] = triangle_centroid(loads[t].p);
    diameters[t] = triangle_diameter(loads[t].p);
  }
  const FarSources far = far_sources(loads);
  const NearLists near = find_near_triangles(x, centroids, diameters, opts.far_ratio);
  const LineRule gl = gauss_legendre_01(opts.singular_points);
  const int n = int(x.size());
  u.resize(n);
  const double t1 = omp_get_wtime();
  // Each node is summed by one thread in a fixed order: results do not depend on the
  // number of threads.
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i)
    u[i] = far_sum(x[i], far);
  const double t2 = omp_get_wtime();
  const NearRule rule = near_rule(opts, gl);
#pragma omp parallel
  {
    PairBuffer points; // the correction points of all near triangles of one node
#pragma omp for schedule(dynamic, 16)
    for (int i = 0; i < n; ++i) {
      points.n = 0;
      for (int k = near.offset[i]; k < near.offset[i + 1]; ++k) {
        const int t = near.triangle[k];
        for_each_correction_point(x[i], vertex_index(topo, i, t), loads[t], rule,
                                  [&](Vec3 r, Vec3 w) { points.push(r, w); });
      }
      u[i] = (-1.0 / (8.0 * kPi)) * (u[i] + stokeslet_sum(points));
    }
  }
  if (timings) {
    timings->setup += t1 - t0;
    timings->far += t2 - t1;
    timings->near += omp_get_wtime() - t2;
    timings->near_pairs += long(near.triangle.size());
  }
}

} // namespace capsim
