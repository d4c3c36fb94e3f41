#include "stokes/single_layer/periodic_single_layer.hpp"

#include "common/vector_clones.hpp"
#include "stokes/cells/periodic_cells.hpp"
#include "stokes/ewald/ewald_reciprocal.hpp"
#include "stokes/ewald/pair_buffer.hpp"
#include "stokes/ewald/real_space_sum.hpp"
#include "stokes/quadrature/near_corrections.hpp"
#include "stokes/quadrature/near_triangle_cells.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <cmath>
#include <omp.h>
#include <stdexcept>

namespace capsim {
namespace {

// The patches of every capsule, one after another.
std::vector<PatchMoments> all_patch_moments(const Topology& topo, int num_capsules,
                                            const std::vector<Vec3>& x,
                                            const std::vector<Vec3>& q, int patch_level) {
  const int nn = topo.num_nodes, mesh_level = icosphere_level(topo);
  std::vector<PatchMoments> all;
  for (int c = 0; c < num_capsules; ++c) {
    std::vector<PatchMoments> p =
        patch_moments(topo, mesh_level, patch_level, &x[c * nn], &q[c * nn]);
    all.insert(all.end(), p.begin(), p.end());
  }
  return all;
}

// What the near corrections of every node read.
struct NearNodes {
  const Topology& topo;
  const std::vector<Vec3>& x;
  const std::vector<TriangleLoad>& loads;
  const std::vector<Vec3>& centroids;
  const std::vector<double>& near_radius;
  const NearTriangleCells& triangle_cells;
  double box;
  NearRule rule;
};

// The near corrections of node i, the sum over the near images of every triangle
// (near_corrections.hpp), with `points` as scratch. Compiled in the vector clones with
// the search and the quadrature's templates inlined (CAPSIM_FLATTEN), so that their
// scalar arithmetic gains FMA and the wider instruction sets: the stage took a tenth less
// (docs/performance.md).
CAPSIM_VECTOR_CLONES CAPSIM_FLATTEN Vec3 node_near_correction(const NearNodes& c, int i,
                                                              PairBuffer& points) {
  const Vec3 xi = c.x[i];
  points.n = 0;
  c.triangle_cells.for_neighbours(xi, [&](int t, Vec3 image) {
    const Vec3 d = xi - image;
    if (dot(d, d) >= c.near_radius[t] * c.near_radius[t])
      return;
    Vec3 shift = image - c.centroids[t]; // a lattice vector, up to round-off
    if (norm(shift) < 1e-9 * c.box)
      shift = {};
    for_each_image_correction_point(xi, vertex_index(c.topo, i, t), c.loads[t], shift,
                                    c.rule, [&](Vec3 r, Vec3 w) { points.push(r, w); });
  });
  return stokeslet_sum(points);
}

} // namespace

void periodic_single_layer_velocity(const Topology& topo, int num_capsules,
                                    const std::vector<Vec3>& x,
                                    const std::vector<Vec3>& q,
                                    const ShearedLattice& lattice,
                                    const EwaldParameters& ewald,
                                    const QuadratureOptions& quad, std::vector<Vec3>& u,
                                    ReciprocalSum reciprocal, PeriodicTimings* timings) {
  const double t0 = omp_get_wtime();
  const int num_tri = int(topo.triangles.size()) * num_capsules;
  std::vector<TriangleLoad> loads(num_tri);
  std::vector<Vec3> centroids(num_tri);
  std::vector<double> diameter(num_tri), near_radius(num_tri);
#pragma omp parallel for schedule(static)
  for (int t = 0; t < num_tri; ++t) {
    loads[t] = triangle_load(topo, x, q, t);
    centroids[t] = triangle_centroid(loads[t].p);
    diameter[t] = triangle_diameter(loads[t].p);
    near_radius[t] = quad.far_ratio * diameter[t];
  }
  const FarSources far = far_sources(loads);
  const NearTriangleCells triangle_cells(lattice, centroids, diameter, quad.far_ratio);
  const LineRule gl = gauss_legendre_01(quad.singular_points);
  const NearNodes near{topo,        x,
                       loads,       centroids,
                       near_radius, triangle_cells,
                       lattice.L,   near_rule(quad, gl)};
  const int n = int(x.size());
  u.assign(n, Vec3{});
  const double t1 = omp_get_wtime();
#pragma omp parallel
  {
    PairBuffer points; // the correction points of all near triangles of one node
#pragma omp for schedule(dynamic, 8)
    for (int i = 0; i < n; ++i)
      u[i] = node_near_correction(near, i, points);
  }
  const double t2 = omp_get_wtime();
  const long pairs = add_real_space_sum(lattice, far, x, ewald, u);
  const double t3 = omp_get_wtime();
  if (reciprocal.spectral)
    reciprocal.spectral->add_reciprocal(lattice, far, x, u,
                                        timings ? &timings->spectral : nullptr);
  else if (reciprocal.patch_level >= 0)
    ewald_reciprocal_patches(
        lattice, x, all_patch_moments(topo, num_capsules, x, q, reciprocal.patch_level),
        ewald, u);
  else
    ewald_reciprocal_direct(lattice, x, far, ewald, u);
  if (timings) {
    timings->setup += t1 - t0;
    timings->near += t2 - t1;
    timings->real_space += t3 - t2;
    timings->reciprocal += omp_get_wtime() - t3;
    timings->real_space_pairs += pairs;
  }
  for (auto& v : u)
    v = (-1.0 / (8.0 * kPi)) * v;
}

} // namespace capsim
