#include "stokes/quadrature/triangle_sources.hpp"

#include "stokes/quadrature/near_corrections.hpp"

namespace capsim {

TriangleLoad triangle_load(const Topology& topo, const std::vector<Vec3>& x,
                           const std::vector<Vec3>& q, int global_triangle) {
  const int nt = int(topo.triangles.size());
  const int offset = (global_triangle / nt) * topo.num_nodes;
  const Triangle& tri = topo.triangles[global_triangle % nt];
  TriangleLoad t;
  for (int k = 0; k < 3; ++k) {
    t.p[k] = x[offset + tri[k]];
    t.q[k] = q[offset + tri[k]];
  }
  return t;
}

long far_rule_points(const Topology& topo, int num_capsules) {
  return long(triangle_rule_3().n) * num_capsules * long(topo.triangles.size());
}

FarSources far_sources(const std::vector<TriangleLoad>& loads) {
  const TriangleRule rule = triangle_rule_3();
  FarSources s;
  for (int a = 0; a < 3; ++a) {
    s.y[a].resize(loads.size() * rule.n);
    s.f[a].resize(loads.size() * rule.n);
  }
  for (size_t t = 0; t < loads.size(); ++t) {
    double area = 0.5 * norm(area_vector2(loads[t].p[0], loads[t].p[1], loads[t].p[2]));
    for (int g = 0; g < rule.n; ++g) {
      Vec3 y = barycentric(loads[t].p, rule.l1[g], rule.l2[g]);
      Vec3 f = (rule.w[g] * area) * barycentric(loads[t].q, rule.l1[g], rule.l2[g]);
      size_t k = t * rule.n + g;
      s.y[0][k] = y.x, s.y[1][k] = y.y, s.y[2][k] = y.z;
      s.f[0][k] = f.x, s.f[1][k] = f.y, s.f[2][k] = f.z;
    }
  }
  return s;
}

int vertex_index(const Topology& topo, int node, int t_global) {
  const int nt = int(topo.triangles.size());
  if (node / topo.num_nodes != t_global / nt)
    return -1;
  for (int k = 0; k < 3; ++k)
    if (topo.triangles[t_global % nt][k] == node % topo.num_nodes)
      return k;
  return -1;
}

NearRule near_rule(const QuadratureOptions& o, const LineRule& gl) {
  NearRule r;
  r.far_ratio = o.far_ratio;
  r.near_ratio = o.near_ratio;
  r.max_depth = o.max_depth;
  r.gl_x = gl.x.data();
  r.gl_w = gl.w.data();
  r.gl_n = int(gl.x.size());
  return r;
}

} // namespace capsim
