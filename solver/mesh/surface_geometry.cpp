#include "mesh/surface_geometry.hpp"

namespace capsim {

double surface_area(const Topology& topo, const Vec3* x) {
  double a = 0;
  for (const auto& t : topo.triangles)
    a += 0.5 * norm(area_vector2(x[t[0]], x[t[1]], x[t[2]]));
  return a;
}

// Each triangle and the origin span a tetrahedron of signed volume x0 . (x1 x x2) / 6.
double enclosed_volume(const Topology& topo, const Vec3* x) {
  double v = 0;
  for (const auto& t : topo.triangles)
    v += dot(x[t[0]], cross(x[t[1]], x[t[2]]));
  return v / 6.0;
}

Vec3 volume_centroid(const Topology& topo, const Vec3* x) {
  Vec3 m;
  double v = 0;
  for (const auto& t : topo.triangles) {
    double vt = dot(x[t[0]], cross(x[t[1]], x[t[2]])) / 6.0;
    v += vt;
    m += (vt / 4.0) * (x[t[0]] + x[t[1]] + x[t[2]]);
  }
  return (1.0 / v) * m;
}

// For a tetrahedron with vertices 0, a, b, c: int x x^T dV = V/20 (sum_k v_k v_k^T + s
// s^T), s = a + b + c. Shifting the origin to the centroid first keeps the sum well
// conditioned.
Mat3 second_moment(const Topology& topo, const Vec3* x, Vec3 c) {
  Mat3 mo;
  for (const auto& t : topo.triangles) {
    Vec3 v[3] = {x[t[0]] - c, x[t[1]] - c, x[t[2]] - c};
    double vt = dot(v[0], cross(v[1], v[2])) / 6.0;
    Vec3 s = v[0] + v[1] + v[2];
    double sa[3] = {s.x, s.y, s.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double acc = sa[i] * sa[j];
        for (const auto& vk : v) {
          double va[3] = {vk.x, vk.y, vk.z};
          acc += va[i] * va[j];
        }
        mo.m[i][j] += vt / 20.0 * acc;
      }
  }
  return mo;
}

std::vector<double> node_areas(const Topology& topo, const Vec3* x) {
  std::vector<double> a(topo.num_nodes, 0.0);
  for (const auto& t : topo.triangles) {
    double third = norm(area_vector2(x[t[0]], x[t[1]], x[t[2]])) / 6.0;
    for (int k : t)
      a[k] += third;
  }
  return a;
}

std::vector<Vec3> node_area_vectors(const Topology& topo, const Vec3* x) {
  std::vector<Vec3> n(topo.num_nodes);
  for (const auto& t : topo.triangles) {
    Vec3 an = area_vector2(x[t[0]], x[t[1]], x[t[2]]);
    for (int k : t)
      n[k] += an;
  }
  return n;
}

std::vector<Vec3> node_normals(const Topology& topo, const Vec3* x) {
  std::vector<Vec3> n = node_area_vectors(topo, x);
  for (auto& v : n)
    v = (1.0 / norm(v)) * v;
  return n;
}

double mean_edge_length(const Topology& topo, const Vec3* x) {
  // Every interior edge is shared by two triangles, so summing all three edges of every
  // triangle counts each edge twice; the mean is unaffected.
  double sum = 0;
  for (const auto& t : topo.triangles)
    for (int k = 0; k < 3; ++k)
      sum += norm(x[t[(k + 1) % 3]] - x[t[k]]);
  return sum / (3.0 * topo.triangles.size());
}

} // namespace capsim
