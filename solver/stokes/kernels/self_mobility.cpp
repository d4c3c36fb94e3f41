#include "stokes/kernels/self_mobility.hpp"

#include "stokes/quadrature/element_integrals.hpp"

namespace capsim {

std::vector<Mat3> self_mobility_blocks(const Topology& topo, const Vec3* x,
                                       const QuadratureOptions& quad) {
  const LineRule gl = gauss_legendre_01(quad.singular_points);
  const int n_gl = int(gl.x.size());
  // Each triangle's three vertex integrals go to their own slots (in parallel: a single
  // capsule's implicit step has no capsules to share among the threads), then to the
  // nodes.
  const int nt = int(topo.triangles.size());
  std::vector<Mat3> part(3 * nt);
  const Vec3 unit[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
#pragma omp parallel for schedule(static)
  for (int e = 0; e < nt; ++e) {
    const auto& t = topo.triangles[e];
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) {
        TriangleLoad load{{x[t[0]], x[t[1]], x[t[2]]}, {}};
        load.q[k] = unit[d];
        const Vec3 col =
            integrate_singular_vertex(k, load, gl.x.data(), gl.w.data(), n_gl);
        part[3 * e + k].m[0][d] = -col.x / (8.0 * kPi);
        part[3 * e + k].m[1][d] = -col.y / (8.0 * kPi);
        part[3 * e + k].m[2][d] = -col.z / (8.0 * kPi);
      }
  }
  std::vector<Mat3> blocks(topo.num_nodes);
  for (int e = 0; e < nt; ++e)
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a)
        for (int d = 0; d < 3; ++d)
          blocks[topo.triangles[e][k]].m[a][d] += part[3 * e + k].m[a][d];
  return blocks;
}

} // namespace capsim
