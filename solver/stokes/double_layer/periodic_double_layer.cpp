#include "stokes/double_layer/periodic_double_layer.hpp"

#include "common/constants.hpp"
#include "mesh/surface_geometry.hpp"
#include "stokes/double_layer/double_layer.hpp"
#include "stokes/double_layer/ewald_stresslet.hpp"
#include "stokes/double_layer/stresslet_real_sum.hpp"
#include "stokes/quadrature/element_integrals.hpp"
#include "stokes/quadrature/near_triangle_cells.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace capsim {
namespace {

// The wave vectors k = m1 b1 + m2 b2 + m3 b3 with 0 < |k| < k_cut in the upper half
// space (one of each pair k, -k; the selection of ewald_reciprocal.cpp).
std::vector<Vec3> half_wave_vectors(const ShearedLattice& g, double k_cut) {
  std::vector<Vec3> ks;
  for_each_wave_vector(g, k_cut, [&](int m1, int m2, int m3, Vec3 k) {
    if (m3 > 0 || (m3 == 0 && (m1 > 0 || (m1 == 0 && m2 > 0))))
      ks.push_back(k);
  });
  return ks;
}

// The factor of the reciprocal sum (3) over half the wave vectors: -(8 pi / V) times 2.
double reciprocal_prefactor(const ShearedLattice& g) {
  return -16.0 * kPi / (g.L * g.L * g.L);
}

} // namespace

PeriodicDoubleLayer::PeriodicDoubleLayer(
    const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
    const ShearedLattice& lattice, const EwaldParameters& ewald,
    const QuadratureOptions& quad, const SpectralParameters* spectral,
    const EwaldParameters* self_ewald, const SpectralParameters* self_grid)
    : topo_(topo), num_capsules_(num_capsules), x_(x), lattice_(lattice), ewald_(ewald),
      quad_(quad), tri_(double_layer_triangles(topo, num_capsules, x)),
      cells_(lattice, ewald.r_cut, tri_.y), k_(half_wave_vectors(lattice, ewald.k_cut)) {
  if (!(ewald.xi > 0 && ewald.r_cut > 0 && ewald.k_cut > 0))
    throw std::invalid_argument("PeriodicDoubleLayer: xi and the cut-offs must be > 0");
  if (spectral)
    spectral_ = std::make_unique<SpectralStresslet>(lattice.L, ewald, *spectral);
  for (int c = 0; c < num_capsules; ++c)
    volume_.push_back(enclosed_volume(topo, &x[size_t(c) * topo.num_nodes]));
  for (const Vec3& k : k_)
    phi_.push_back(stresslet_fourier_screening(dot(k, k), ewald.xi));
  setup_near_lists();
  setup_near_matrices();
  if (!self_ewald != !self_grid)
    throw std::invalid_argument(
        "PeriodicDoubleLayer: the self matrices' split needs both "
        "its parameters and its grid");
  setup_self_matrices(spectral ? self_ewald : nullptr, self_grid);
}

// Every node's triangle images closer than far_ratio diameters (by centroid), with the
// lattice vector to the image.
void PeriodicDoubleLayer::setup_near_lists() {
  const NearTriangleCells cells(lattice_, tri_.centroid, tri_.diameter, quad_.far_ratio);
  near_offset_.assign(1, 0);
  for (const Vec3& xi : x_) {
    cells.for_neighbours(xi, [&](int t, Vec3 image) {
      const Vec3 d = xi - image;
      const double reach = quad_.far_ratio * tri_.diameter[t];
      if (dot(d, d) >= reach * reach)
        return;
      Vec3 shift = image - tri_.centroid[t]; // a lattice vector, up to round-off
      if (norm(shift) < 1e-9 * lattice_.L)
        shift = Vec3{};
      near_.push_back({t, shift});
    });
    near_offset_.push_back(int(near_.size()));
  }
}

// self_: the far rule of T^per(x_i - y) . n over node i's own capsule and its images,
// real space (own capsule's points within r_cut) plus reciprocal space (per capsule
// structure factors B_c(k) = sum_{g in c} a_g exp(-i k . y_g), then
// -(8 pi / V) sum_k phi A(k) Im[exp(i k . x_i) B_c(k)]; with Spectral Ewald one grid
// pass per capsule, SpectralStresslet::add_group_matrices).
void PeriodicDoubleLayer::setup_self_matrices(const EwaldParameters* self_ewald,
                                              const SpectralParameters* self_grid) {
  for (auto& s : self_)
    s.assign(num_nodes(), 0.0);
  // The real-space part at the self matrices' own split, where they have one.
  add_self_real_space(self_ewald ? *self_ewald : ewald_);
  const size_t per_capsule = topo_.triangles.size() * triangle_rule_3().n;
  if (self_ewald)
    SpectralStresslet(lattice_.L, *self_ewald, *self_grid)
        .add_group_matrices(lattice_, tri_.y, tri_.a, per_capsule, x_,
                            size_t(topo_.num_nodes), self_);
  else if (spectral_)
    spectral_->add_group_matrices(lattice_, tri_.y, tri_.a, per_capsule, x_,
                                  size_t(topo_.num_nodes), self_);
  else
    add_self_reciprocal_direct();
}

// The real-space part of self_: per capsule a cell list of its own rule points only (the
// other capsules' points, most of the sphere at a dense suspension's self split, are
// never visited); per node the pairs within r_cut are gathered and summed in one
// vectorised loop.
void PeriodicDoubleLayer::add_self_real_space(const EwaldParameters& ew) {
  const size_t per_capsule = topo_.triangles.size() * triangle_rule_3().n;
  const double rc2 = ew.r_cut * ew.r_cut;
  for (int c = 0; c < num_capsules_; ++c) {
    const auto first = tri_.y.begin() + c * per_capsule;
    const PeriodicCells cells(lattice_, ew.r_cut, {first, first + per_capsule},
                              PeriodicCells::Index::table, 2.0);
    std::vector<Vec3> a(cells.size());
    for (int j = 0; j < cells.size(); ++j)
      a[j] = tri_.a[c * per_capsule + cells.point(j)];
#pragma omp parallel
    {
      PairBuffer b; // separations r and normals a
      b.reserve(1024);
#pragma omp for schedule(dynamic, 16)
      for (int i = c * topo_.num_nodes; i < (c + 1) * topo_.num_nodes; ++i) {
        cells.gather_within(x_[i], rc2, b, [&](size_t m, int j, Vec3 xs) {
          const Vec3 r = xs - cells.wrapped(j);
          b.rx[m] = r.x, b.ry[m] = r.y, b.rz[m] = r.z;
          b.fx[m] = a[j].x, b.fy[m] = a[j].y, b.fz[m] = a[j].z;
          return dot(r, r);
        });
        double m[6] = {0, 0, 0, 0, 0, 0};
        stresslet_real_matrix_sum(b, ew.xi, m);
        for (int k = 0; k < 6; ++k)
          self_[k][i] += m[k];
      }
    }
  }
}

// The reciprocal part of self_ by the direct sum over the wave vectors (the reference).
void PeriodicDoubleLayer::add_self_reciprocal_direct() {
  const int nk = int(k_.size());
  const size_t per_capsule = topo_.triangles.size() * triangle_rule_3().n;
  // B_c(k): [capsule][k] real and imaginary vectors.
  std::vector<Vec3> b_re(size_t(num_capsules_) * nk), b_im(b_re.size());
#pragma omp parallel for schedule(static)
  for (int kk = 0; kk < nk; ++kk)
    for (size_t g = 0; g < tri_.y.size(); ++g) {
      const double th = dot(k_[kk], tri_.y[g]);
      const size_t j = (g / per_capsule) * nk + kk;
      b_re[j] += std::cos(th) * tri_.a[g];
      b_im[j] -= std::sin(th) * tri_.a[g];
    }
  const double pre = reciprocal_prefactor(lattice_);
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < num_nodes(); ++i) {
    const int own = i / topo_.num_nodes;
    double f[6] = {0, 0, 0, 0, 0, 0};
    for (int kk = 0; kk < nk; ++kk) {
      const double th = dot(k_[kk], x_[i]), c = std::cos(th), s = std::sin(th);
      const size_t j = size_t(own) * nk + kk;
      // Im[(c + i s)(B_re + i B_im)] = s B_re + c B_im
      stresslet_fourier_add_matrix(k_[kk], phi_[kk] * (s * b_re[j] + c * b_im[j]), f);
    }
    for (int c = 0; c < 6; ++c)
      self_[c][i] += pre * f[c];
  }
}

std::vector<Vec3> PeriodicDoubleLayer::rule_densities(const std::vector<Vec3>& u) const {
  const TriangleRule rule = triangle_rule_3();
  const int nt = int(tri_.area.size());
  std::vector<Vec3> ug(size_t(nt) * rule.n);
  for (int t = 0; t < nt; ++t) {
    const TriangleLoad load = triangle_load(topo_, x_, u, t);
    for (int g = 0; g < rule.n; ++g)
      ug[size_t(t) * rule.n + g] = barycentric(load.q, rule.l1[g], rule.l2[g]);
  }
  return ug;
}

// sum over all rule points' images within r_cut of u_g . T^R(x_i - y_g) . a_g: per node
// the pairs are gathered from the cell runs into a buffer and summed in one vectorised
// loop.
void PeriodicDoubleLayer::add_real_space(const std::vector<Vec3>& ug,
                                         std::vector<Vec3>& sum) const {
  // sym(u_g a_g^T) of the sources in cell order.
  std::vector<std::array<double, 6>> d(cells_.size());
  for (int j = 0; j < cells_.size(); ++j) {
    const int g = cells_.point(j);
    symmetric_product(ug[g], tri_.a[g], d[j].data());
  }
  const double rc2 = ewald_.r_cut * ewald_.r_cut;
#pragma omp parallel
  {
    StressletPairBuffer b;
    b.reserve(1024);
#pragma omp for schedule(dynamic, 16)
    for (int i = 0; i < num_nodes(); ++i) {
      cells_.gather_within(x_[i], rc2, b, [&](size_t m, int j, Vec3 xs) {
        const Vec3 r = xs - cells_.wrapped(j);
        b.r[0][m] = r.x, b.r[1][m] = r.y, b.r[2][m] = r.z;
        for (int c = 0; c < 6; ++c)
          b.d[c][m] = d[j][c];
        return dot(r, r);
      });
      sum[i] += stresslet_real_sum(b, ewald_.xi);
    }
  }
}

// -(8 pi / V) sum_{k != 0} phi(k) Im[exp(i k . x_i) Q(k)] (3), with the structure factor
// Q_j(k) = sum_g u_gi A_ijl(k) a_gl exp(-i k . y_g), over half the wave vectors, twice.
void PeriodicDoubleLayer::add_reciprocal(const std::vector<Vec3>& ug,
                                         std::vector<Vec3>& sum) const {
  if (spectral_) {
    // The grid carries the symmetric part of u_g a_g^T: A(k) is fully symmetric, so the
    // contraction sees only it (stresslet_spectral_mode).
    StressletSources src;
    const size_t ng = tri_.y.size();
    for (auto& c : src.y)
      c.resize(ng);
    for (auto& c : src.d)
      c.resize(ng);
    for (size_t g = 0; g < ng; ++g) {
      src.y[0][g] = tri_.y[g].x, src.y[1][g] = tri_.y[g].y, src.y[2][g] = tri_.y[g].z;
      double d[6];
      symmetric_product(ug[g], tri_.a[g], d);
      for (int c = 0; c < 6; ++c)
        src.d[c][g] = d[c];
    }
    spectral_->add_reciprocal(lattice_, src, x_, sum);
    return;
  }
  const int nk = int(k_.size());
  std::vector<Vec3> q_re(nk), q_im(nk);
#pragma omp parallel for schedule(static)
  for (int kk = 0; kk < nk; ++kk) {
    Vec3 re, im;
    for (size_t g = 0; g < tri_.y.size(); ++g) {
      const Vec3 w = stresslet_fourier_apply(k_[kk], ug[g], tri_.a[g]);
      const double th = dot(k_[kk], tri_.y[g]);
      re += std::cos(th) * w;
      im -= std::sin(th) * w;
    }
    q_re[kk] = phi_[kk] * re;
    q_im[kk] = phi_[kk] * im;
  }
  const double pre = reciprocal_prefactor(lattice_);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < num_nodes(); ++i) {
    Vec3 s;
    for (int kk = 0; kk < nk; ++kk) {
      const double th = dot(k_[kk], x_[i]);
      s += std::sin(th) * q_re[kk] + std::cos(th) * q_im[kk];
    }
    sum[i] += pre * s;
  }
}

// The near corrections' matrices of every near pair: the free-space accurate integral
// minus the 3-point rule over the triangle's image, as a map of its vertex densities.
void PeriodicDoubleLayer::setup_near_matrices() {
  near_matrix_.resize(18 * near_.size());
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < num_nodes(); ++i)
    for (int p = near_offset_[i]; p < near_offset_[i + 1]; ++p)
      double_layer_near_pair_matrices(topo_, x_, tri_, quad_, i, near_[p].triangle,
                                      near_[p].shift, &near_matrix_[18 * size_t(p)]);
}

// The near corrections of node i: sum over its near triangle images of their matrices
// times (u - sub) at the vertices, sub on its own capsule's only.
Vec3 PeriodicDoubleLayer::near_correction(int i, const std::vector<Vec3>& u,
                                          Vec3 sub) const {
  const int own = i / topo_.num_nodes, nt_capsule = int(topo_.triangles.size());
  Vec3 s;
  for (int p = near_offset_[i]; p < near_offset_[i + 1]; ++p) {
    const int t = near_[p].triangle;
    s += double_layer_near_apply(&near_matrix_[18 * size_t(p)],
                                 triangle_load(topo_, x_, u, t).q,
                                 t / nt_capsule == own ? sub : Vec3{});
  }
  return s;
}

void PeriodicDoubleLayer::apply(const std::vector<Vec3>& u, std::vector<Vec3>& k,
                                bool subtract) const {
  const int n = num_nodes();
  if (int(u.size()) != n)
    throw std::invalid_argument(
        "PeriodicDoubleLayer::apply: one density vector per node needed");
  const std::vector<Vec3> ug = rule_densities(u);
  std::vector<Vec3> sum(n, Vec3{});
  add_real_space(ug, sum);
  add_reciprocal(ug, sum);
  k.resize(n);
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < n; ++i) {
    const Vec3 ui = subtract ? u[i] : Vec3{};
    Vec3 s = sum[i] + near_correction(i, u, ui);
    if (subtract) {
      double m[6];
      for (int c = 0; c < 6; ++c)
        m[c] = self_[c][i];
      s -= symmetric_matrix_apply(m, ui);
    }
    // The subtracted constant's integral by the periodic identity (4).
    const double v =
        volume_[i / topo_.num_nodes] / (lattice_.L * lattice_.L * lattice_.L);
    k[i] = (1.0 / (8.0 * kPi)) * s + (subtract ? 0.5 - v : 0.0) * ui;
  }
}

void periodic_double_layer_velocity(const Topology& topo, int num_capsules,
                                    const std::vector<Vec3>& x,
                                    const std::vector<Vec3>& u,
                                    const ShearedLattice& lattice,
                                    const EwaldParameters& ewald,
                                    const QuadratureOptions& quad, std::vector<Vec3>& k) {
  PeriodicDoubleLayer(topo, num_capsules, x, lattice, ewald, quad).apply(u, k);
}

} // namespace capsim
