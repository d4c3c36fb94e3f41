#include "stokes/self_mobility.hpp"

#include "stokes/element_integrals.hpp"

namespace capsim {

std::vector<Mat3> self_mobility_blocks(const Topology& topo, const Vec3* x,
                                       const QuadratureOptions& quad) {
  const LineRule gl = gauss_legendre_01(quad.singular_points);
  const int n_gl = int(gl.x.size());
  std::vector<Mat3> blocks(topo.num_nodes);
  const Vec3 unit[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& t : topo.triangles)
    for (int k = 0; k < 3; ++k) {
      Mat3& b = blocks[t[k]];
      for (int d = 0; d < 3; ++d) {
        TriangleLoad load{{x[t[0]], x[t[1]], x[t[2]]}, {}};
        load.q[k] = unit[d];
        const Vec3 col =
            integrate_singular_vertex(k, load, gl.x.data(), gl.w.data(), n_gl);
        b.m[0][d] -= col.x / (8.0 * kPi);
        b.m[1][d] -= col.y / (8.0 * kPi);
        b.m[2][d] -= col.z / (8.0 * kPi);
      }
    }
  return blocks;
}

} // namespace capsim
