#include "stokes/double_layer/double_layer.hpp"

#include "common/constants.hpp"
#include "common/vector_clones.hpp"
#include "stokes/quadrature/element_integrals.hpp"
#include "stokes/quadrature/near_triangles.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <algorithm>
#include <stdexcept>

namespace capsim {
namespace {

// sum_g u_g . T(x - y_g) . a_g over all far-rule points (the dense part), branch-free and
// structure-of-arrays so that it vectorises, as far_sum in single_layer.cpp.
CAPSIM_VECTOR_CLONES Vec3 far_sum(Vec3 x, size_t n, const double* const y[3],
                                  const double* const a[3], const double* const u[3]) {
  const double *yx = y[0], *yy = y[1], *yz = y[2];
  const double *ax = a[0], *ay = a[1], *az = a[2];
  const double *ux = u[0], *uy = u[1], *uz = u[2];
  double kx = 0, ky = 0, kz = 0;
#pragma omp simd reduction(+ : kx, ky, kz)
  for (size_t g = 0; g < n; ++g) {
    const double rx = x.x - yx[g], ry = x.y - yy[g], rz = x.z - yz[g];
    const double r2 = rx * rx + ry * ry + rz * rz, rinv = 1.0 / std::sqrt(r2);
    const double rinv2 = rinv * rinv;
    const double s = -6.0 * (ux[g] * rx + uy[g] * ry + uz[g] * rz) *
                     (ax[g] * rx + ay[g] * ry + az[g] * rz) * rinv2 * rinv2 * rinv;
    kx += s * rx;
    ky += s * ry;
    kz += s * rz;
  }
  return {kx, ky, kz};
}

} // namespace

DoubleLayerTriangles double_layer_triangles(const Topology& topo, int num_capsules,
                                            const std::vector<Vec3>& x) {
  if (int(x.size()) != topo.num_nodes * num_capsules)
    throw std::invalid_argument(
        "double layer: num_capsules * num_nodes positions needed");
  const int nt = int(topo.triangles.size()) * num_capsules;
  const TriangleRule rule = triangle_rule_3();
  DoubleLayerTriangles tri;
  tri.unit_normal.resize(nt);
  tri.area.resize(nt);
  tri.centroid.resize(nt);
  tri.diameter.resize(nt);
  tri.y.resize(size_t(nt) * rule.n);
  tri.a.resize(size_t(nt) * rule.n);
  for (int t = 0; t < nt; ++t) {
    const TriangleLoad load = triangle_load(topo, x, x, t);
    const Vec3 av = area_vector2(load.p[0], load.p[1], load.p[2]);
    tri.area[t] = 0.5 * norm(av);
    tri.unit_normal[t] = (1.0 / norm(av)) * av; // outward: counter-clockwise from outside
    tri.centroid[t] = triangle_centroid(load.p);
    tri.diameter[t] = triangle_diameter(load.p);
    for (int g = 0; g < rule.n; ++g) {
      const size_t k = size_t(t) * rule.n + g;
      tri.y[k] = barycentric(load.p, rule.l1[g], rule.l2[g]);
      tri.a[k] = (rule.w[g] * tri.area[t]) * tri.unit_normal[t];
    }
  }
  return tri;
}

void double_layer_near_pair_matrices(const Topology& topo, const std::vector<Vec3>& x,
                                     const DoubleLayerTriangles& tri,
                                     const QuadratureOptions& opts, int i, int t,
                                     Vec3 shift, double* m) {
  TriangleLoad load = triangle_load(topo, x, x, t);
  for (auto& v : load.p)
    v += shift;
  const bool own_vertex = dot(shift, shift) == 0 && vertex_index(topo, i, t) >= 0;
  double mv[3][6];
  double_layer_near_matrices(x[i], own_vertex, load.p, tri.unit_normal[t], tri.area[t],
                             opts.near_ratio, opts.max_depth, mv);
  std::copy(&mv[0][0], &mv[0][0] + 18, m);
}

DoubleLayer::DoubleLayer(const Topology& topo, int num_capsules,
                         const std::vector<Vec3>& x, const QuadratureOptions& opts)
    : topo_(topo), num_capsules_(num_capsules), x_(x), opts_(opts),
      tri_(double_layer_triangles(topo, num_capsules, x)) {
  const TriangleRule rule = triangle_rule_3();
  for (int c = 0; c < 3; ++c)
    y_[c].resize(tri_.y.size()), a_[c].resize(tri_.a.size());
  for (size_t k = 0; k < tri_.y.size(); ++k) {
    y_[0][k] = tri_.y[k].x, y_[1][k] = tri_.y[k].y, y_[2][k] = tri_.y[k].z;
    a_[0][k] = tri_.a[k].x, a_[1][k] = tri_.a[k].y, a_[2][k] = tri_.a[k].z;
  }
  const NearLists near =
      find_near_triangles(x_, tri_.centroid, tri_.diameter, opts.far_ratio);
  near_offset_ = near.offset;
  near_triangle_ = near.triangle;
  near_matrix_.resize(18 * near_triangle_.size());
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < num_nodes(); ++i)
    for (int p = near_offset_[i]; p < near_offset_[i + 1]; ++p)
      double_layer_near_pair_matrices(topo_, x_, tri_, opts_, i, near_triangle_[p],
                                      Vec3{}, &near_matrix_[18 * size_t(p)]);
  // The far rule of T(x_i - y) . n over node i's own capsule (the subtracted constant's
  // factor); the near triangles' share is corrected in apply.
  const int n = num_nodes();
  for (auto& s : self_)
    s.assign(n, 0.0);
  const size_t per_capsule = topo.triangles.size() * rule.n;
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    const size_t g0 = size_t(i / topo.num_nodes) * per_capsule;
    double m[6] = {0, 0, 0, 0, 0, 0};
    for (size_t g = g0; g < g0 + per_capsule; ++g) {
      const Vec3 r = x_[i] - Vec3{y_[0][g], y_[1][g], y_[2][g]};
      const Vec3 a{a_[0][g], a_[1][g], a_[2][g]};
      const double r2 = dot(r, r), rinv = 1.0 / std::sqrt(r2);
      const double s = -6.0 * dot(a, r) * rinv * rinv * rinv * rinv * rinv;
      m[0] += s * r.x * r.x, m[1] += s * r.y * r.y, m[2] += s * r.z * r.z;
      m[3] += s * r.x * r.y, m[4] += s * r.x * r.z, m[5] += s * r.y * r.z;
    }
    for (int c = 0; c < 6; ++c)
      self_[c][i] = m[c];
  }
}

void DoubleLayer::rule_densities(const std::vector<Vec3>& u,
                                 std::vector<double> (&ug)[3]) const {
  const int nt = int(tri_.area.size());
  const TriangleRule rule = triangle_rule_3();
  for (auto& v : ug)
    v.resize(size_t(nt) * rule.n);
  for (int t = 0; t < nt; ++t) {
    const TriangleLoad load = triangle_load(topo_, x_, u, t);
    for (int g = 0; g < rule.n; ++g) {
      const Vec3 v = barycentric(load.q, rule.l1[g], rule.l2[g]);
      const size_t j = size_t(t) * rule.n + g;
      ug[0][j] = v.x, ug[1][j] = v.y, ug[2][j] = v.z;
    }
  }
}

void DoubleLayer::apply(const std::vector<Vec3>& u, std::vector<Vec3>& k,
                        bool subtract) const {
  const int n = num_nodes();
  if (int(u.size()) != n)
    throw std::invalid_argument("DoubleLayer::apply: one density vector per node needed");
  std::vector<double> ug[3];
  rule_densities(u, ug);
  const double* y[3] = {y_[0].data(), y_[1].data(), y_[2].data()};
  const double* a[3] = {a_[0].data(), a_[1].data(), a_[2].data()};
  const double* up[3] = {ug[0].data(), ug[1].data(), ug[2].data()};
  k.resize(n);
  const int nt_capsule = int(topo_.triangles.size());
  // One thread sums each node in a fixed order: the result does not depend on the
  // number of threads.
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < n; ++i) {
    Vec3 sum = far_sum(x_[i], y_[0].size(), y, a, up);
    const Vec3 ui = subtract ? u[i] : Vec3{};
    if (subtract) {
      double m[6];
      for (int c = 0; c < 6; ++c)
        m[c] = self_[c][i];
      sum -= symmetric_matrix_apply(m, ui);
    }
    const int own = i / topo_.num_nodes;
    for (int p = near_offset_[i]; p < near_offset_[i + 1]; ++p) {
      const int t = near_triangle_[p];
      sum += double_layer_near_apply(&near_matrix_[18 * size_t(p)],
                                     triangle_load(topo_, x_, u, t).q,
                                     t / nt_capsule == own ? ui : Vec3{});
    }
    // The subtracted constant's integral by the on-surface identity: 4 pi u(x_i).
    k[i] = (1.0 / (8.0 * kPi)) * sum + (subtract ? 0.5 : 0.0) * ui;
  }
}

void DoubleLayer::apply_at(const std::vector<Vec3>& targets, const std::vector<Vec3>& u,
                           std::vector<Vec3>& k) const {
  if (int(u.size()) != num_nodes())
    throw std::invalid_argument(
        "DoubleLayer::apply_at: one density vector per node needed");
  std::vector<double> ug[3];
  rule_densities(u, ug);
  const double* y[3] = {y_[0].data(), y_[1].data(), y_[2].data()};
  const double* a[3] = {a_[0].data(), a_[1].data(), a_[2].data()};
  const double* up[3] = {ug[0].data(), ug[1].data(), ug[2].data()};
  const NearLists near =
      find_near_triangles(targets, tri_.centroid, tri_.diameter, opts_.far_ratio);
  k.resize(targets.size());
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < int(targets.size()); ++i) {
    Vec3 sum = far_sum(targets[i], y_[0].size(), y, a, up);
    for (int p = near.offset[i]; p < near.offset[i + 1]; ++p) {
      const int t = near.triangle[p];
      sum += double_layer_near_correction(
          targets[i], false, triangle_load(topo_, x_, u, t), tri_.unit_normal[t], Vec3{},
          tri_.area[t], opts_.near_ratio, opts_.max_depth);
    }
    k[i] = (1.0 / (8.0 * kPi)) * sum;
  }
}

void double_layer_velocity(const Topology& topo, int num_capsules,
                           const std::vector<Vec3>& x, const std::vector<Vec3>& u,
                           const QuadratureOptions& opts, std::vector<Vec3>& k) {
  DoubleLayer(topo, num_capsules, x, opts).apply(u, k);
}

} // namespace capsim
