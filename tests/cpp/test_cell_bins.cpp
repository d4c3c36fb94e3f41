// The binned neighbour sums of the GPU backend (stokes/cells/cell_bins.hpp, binned_sums.hpp),
// run on the CPU: the stencil finds exactly the images within reach, and the binned
// screened sum and near corrections equal the all-pairs nearest-image sums.
#include "membrane/membrane_forces.hpp"
#include "mesh/icosphere.hpp"
#include "stokes/cells/binned_sums.hpp"
#include "stokes/quadrature/triangle_sources.hpp"
#include "test_helpers.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <random>

using namespace capsim;

namespace {

// Host version of the device binning: a counting sort by cell. Returns the bins over
// `start`, the wrapped points in bin order and, in `order`, their original indices.
CellBins bin_points(const ShearedLattice& g, double reach, const std::vector<Vec3>& p,
                    std::vector<int>& start, std::vector<Vec3>& wrapped,
                    std::vector<int>& order) {
  const int n = bins_per_side(g.L, reach);
  std::vector<int> key(p.size());
  std::vector<Vec3> w(p.size());
  start.assign(size_t(n) * n * n + 1, 0);
  for (size_t i = 0; i < p.size(); ++i) {
    key[i] = bin_of(g, n, p[i], w[i]);
    ++start[key[i] + 1];
  }
  for (size_t c = 1; c < start.size(); ++c)
    start[c] += start[c - 1];
  std::vector<int> fill(start.begin(), start.end() - 1);
  order.assign(p.size(), 0);
  wrapped.assign(p.size(), Vec3{});
  for (size_t i = 0; i < p.size(); ++i) {
    order[fill[key[i]]] = int(i);
    wrapped[fill[key[i]]++] = w[i];
  }
  return {g, n, start.data()};
}

std::vector<Vec3> random_points(int count, double L, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.7 * L, 1.3 * L); // some outside the cell
  std::vector<Vec3> p(count);
  for (auto& v : p)
    v = {u(rng), u(rng), u(rng)};
  return p;
}

} // namespace

TEST_CASE("cell bins: the stencil visits every image within reach exactly once",
          "[cell_bins]") {
  for (double strain : {0.0, 0.37, -0.5}) {
    const ShearedLattice g = make_sheared_lattice(6.0, strain);
    for (double reach : {6.0 / 5, 6.0 / 7.5}) {
      const auto points = random_points(400, g.L, 7);
      std::vector<int> start, order;
      std::vector<Vec3> wrapped;
      const CellBins b = bin_points(g, reach, points, start, wrapped, order);
      REQUIRE(bins_usable(b.n));
      for (const Vec3& x : random_points(50, g.L, 11)) {
        std::vector<int> found, expected;
        for_each_binned_neighbour(b, x, [&](int j, Vec3 shift) {
          if (norm(x - (wrapped[j] + shift)) < reach)
            found.push_back(order[j]);
        });
        for (size_t i = 0; i < points.size(); ++i) // reach < L/2: one image at most
          if (norm(wrap_to_cell(g, x - points[i])) < reach)
            expected.push_back(int(i));
        std::sort(found.begin(), found.end());
        INFO("strain " << strain << ", reach " << reach);
        CHECK(found == expected);
      }
    }
  }
}

TEST_CASE("cell bins: binned screened sum and near corrections equal the all-pairs "
          "nearest-image sums",
          "[cell_bins]") {
  // Two level-2 capsules with a membrane load, one straddling the boundary.
  const Icosphere mesh = make_icosphere(2);
  const Topology& topo = mesh.topology;
  auto shape = testing::stretched(mesh.positions, 1.3, 0.8, 0.96, 0.5);
  Membrane m(topo, mesh.positions.data(), 1.0);
  std::vector<Vec3> grad, qc, x, q;
  m.energy_gradient(shape.data(), grad);
  m.nodal_load(shape.data(), grad, LoadMapping::lumped, qc);
  for (Vec3 c : {Vec3{0.2, 0.1, 0.0}, Vec3{2.9, 2.4, -0.3}})
    for (int i = 0; i < topo.num_nodes; ++i) {
      x.push_back(shape[i] + c);
      q.push_back(qc[i]);
    }
  const ShearedLattice g = make_sheared_lattice(6.0, 0.3);
  const int num_tri = 2 * int(topo.triangles.size());
  std::vector<TriangleLoad> loads(num_tri);
  std::vector<Vec3> centroids(num_tri);
  double max_diam = 0;
  for (int t = 0; t < num_tri; ++t) {
    loads[t] = triangle_load(topo, x, q, t);
    centroids[t] = triangle_centroid(loads[t].p);
    max_diam = std::max(max_diam, triangle_diameter(loads[t].p));
  }
  const FarSources far = far_sources(loads);
  std::vector<Vec3> y(far.size()), f(far.size());
  for (size_t j = 0; j < far.size(); ++j) {
    y[j] = {far.y[0][j], far.y[1][j], far.y[2][j]};
    f[j] = {far.f[0][j], far.f[1][j], far.f[2][j]};
  }
  const double xi = 3.0, r_cut = 1.1;
  std::vector<int> src_start, src_order, tri_start, tri_order;
  std::vector<Vec3> ys, tri_wc;
  const CellBins src = bin_points(g, r_cut, y, src_start, ys, src_order);
  std::vector<Vec3> fs(f.size());
  for (size_t j = 0; j < f.size(); ++j)
    fs[j] = f[src_order[j]];
  const LineRule gl = gauss_legendre_01(QuadratureOptions{}.singular_points);
  const NearRule rule = near_rule(QuadratureOptions{}, gl);
  const CellBins tri =
      bin_points(g, rule.far_ratio * max_diam, centroids, tri_start, tri_wc, tri_order);
  REQUIRE(bins_usable(src.n));
  REQUIRE(bins_usable(tri.n));
  double far_diff = 0, far_max = 0, near_diff = 0, near_max = 0;
  for (int i = 0; i < int(x.size()); i += 7) {
    Vec3 brute;
    for (size_t j = 0; j < y.size(); ++j) {
      const Vec3 r = wrap_to_cell(g, x[i] - y[j]);
      if (dot(r, r) < r_cut * r_cut)
        brute += ewald_real_apply(r, f[j], xi);
    }
    const Vec3 binned = binned_screened_sum(src, ys.data(), fs.data(), xi, r_cut, x[i]);
    far_diff = std::max(far_diff, norm(binned - brute));
    far_max = std::max(far_max, norm(brute));
    Vec3 near_brute;
    for (int t = 0; t < num_tri; ++t)
      near_brute += nearest_image_near_correction(g, x[i], vertex_index(topo, i, t),
                                                  loads[t], rule);
    const Vec3 near =
        binned_near_corrections(tri, tri_order.data(), tri_wc.data(), loads.data(), rule,
                                x[i], [&](int t) { return vertex_index(topo, i, t); });
    near_diff = std::max(near_diff, norm(near - near_brute));
    near_max = std::max(near_max, norm(near_brute));
  }
  CHECK(far_max > 0);
  CHECK(near_max > 0);
  CHECK(far_diff < 1e-12 * far_max); // the same terms in another order
  CHECK(near_diff < 1e-12 * near_max);
}
