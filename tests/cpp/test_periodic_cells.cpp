#include "stokes/cells/periodic_cells.hpp"
#include "stokes/quadrature/near_triangle_cells.hpp"
#include "stokes/quadrature/near_triangles.hpp"

#include <catch2/catch.hpp>
#include <random>

using namespace capsim;

TEST_CASE("periodic cells: every image within reach is found once, on a sheared box, "
          "whatever the number of cells",
          "[cells]") {
  const double L = 7.0;
  // 35, 16, 7 and 2 cells per side (the first two far more cells than points); 9 > L
  // needs a wider stencil.
  for (double reach : {0.6, 1.3, 3.0, 9.0}) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-3.0, 10.0); // also outside the primary cell
    std::vector<Vec3> points(400);
    for (auto& p : points)
      p = {u(rng), u(rng), u(rng)};
    for (double strain : {0.0, 0.5, -0.37}) {
      ShearedLattice g = make_sheared_lattice(L, strain);
      PeriodicCells cells(g, reach, points);
      PeriodicCells searched(g, reach, points, PeriodicCells::Index::search);
      for (int t = 0; t < 50; ++t) {
        // Half the queries beside a point, so that short reaches find neighbours too.
        Vec3 x =
            t % 2 ? points[t] + Vec3{0.1, -0.05, 0.02} : Vec3{u(rng), u(rng), u(rng)};
        std::vector<int> found;
        cells.for_neighbours(x, [&](int i, Vec3 image) {
          if (norm(image - x) < reach) {
            found.push_back(i);
            // The image is the point moved by a lattice vector.
            Vec3 d = wrap_to_cell(g, image - points[i]);
            CHECK(norm(d) < 1e-9);
          }
        });
        std::vector<int> expected; // every image within reach, by brute force
        for (size_t i = 0; i < points.size(); ++i) {
          Vec3 r0 = wrap_to_cell(g, x - points[i]);
          for (int n3 = -3; n3 <= 3; ++n3)
            for (int n2 = -3; n2 <= 3; ++n2)
              for (int n1 = -4; n1 <= 4; ++n1)
                if (norm(r0 + lattice_point(g, n1, n2, n3)) < reach)
                  expected.push_back(int(i));
        }
        // The searched index visits the same images in the same order (sums over them
        // give the same bits).
        std::vector<std::pair<int, Vec3>> in_table, in_search;
        cells.for_neighbours(x, [&](int i, Vec3 image) {
          in_table.push_back({i, image});
        });
        searched.for_neighbours(x, [&](int i, Vec3 image) {
          in_search.push_back({i, image});
        });
        REQUIRE(in_search.size() == in_table.size());
        for (size_t k = 0; k < in_table.size(); ++k)
          CHECK((in_search[k].first == in_table[k].first &&
                 in_search[k].second.x == in_table[k].second.x &&
                 in_search[k].second.y == in_table[k].second.y &&
                 in_search[k].second.z == in_table[k].second.z));
        std::sort(expected.begin(), expected.end());
        std::sort(found.begin(), found.end());
        CHECK(found == expected);
        // Wider cells (the real-space and near-triangle searches') find the same images.
        for (double cells_per_reach : {2.0, 1.5}) {
          const PeriodicCells wide(g, reach, points, PeriodicCells::Index::table,
                                   cells_per_reach);
          std::vector<int> found_wide;
          wide.for_neighbours(x, [&](int i, Vec3 image) {
            if (norm(image - x) < reach)
              found_wide.push_back(i);
          });
          std::sort(found_wide.begin(), found_wide.end());
          CHECK(found_wide == expected);
        }
      }
    }
  }
}

TEST_CASE("near triangle cells: every centroid image within far_ratio times its own "
          "diameter is found once, long triangles included",
          "[cells]") {
  const double L = 7.0, far_ratio = 2.0;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, L), small(0.1, 0.3);
  std::vector<Vec3> centroids(600);
  std::vector<double> diameters(600);
  for (size_t t = 0; t < centroids.size(); ++t) {
    centroids[t] = {u(rng), u(rng), u(rng)};
    diameters[t] = t % 100 == 7 ? 2.5 : small(rng); // six long ones: reach 5 > L / 2
  }
  for (double strain : {0.0, 0.45}) {
    ShearedLattice g = make_sheared_lattice(L, strain);
    NearTriangleCells cells(g, centroids, diameters, far_ratio);
    for (int k = 0; k < 60; ++k) {
      Vec3 x{u(rng), u(rng), u(rng)};
      std::vector<int> found, expected;
      cells.for_neighbours(x, [&](int t, Vec3 image) {
        if (norm(image - x) < far_ratio * diameters[t])
          found.push_back(t);
      });
      for (size_t t = 0; t < centroids.size(); ++t) {
        Vec3 r0 = wrap_to_cell(g, x - centroids[t]);
        for (int n3 = -2; n3 <= 2; ++n3)
          for (int n2 = -2; n2 <= 2; ++n2)
            for (int n1 = -3; n1 <= 3; ++n1)
              if (norm(r0 + lattice_point(g, n1, n2, n3)) < far_ratio * diameters[t])
                expected.push_back(int(t));
      }
      std::sort(expected.begin(), expected.end());
      std::sort(found.begin(), found.end());
      CHECK(found == expected);
    }
  }
}

TEST_CASE("near triangles (free space): every centroid within far_ratio times its own "
          "diameter is found once, long triangles included",
          "[cells]") {
  const double far_ratio = 2.0;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-3.0, 3.0), small(0.1, 0.3);
  std::vector<Vec3> centroids(500), nodes(80);
  std::vector<double> diameters(500);
  for (size_t t = 0; t < centroids.size(); ++t) {
    centroids[t] = {u(rng), u(rng), 1.5 * u(rng)};  // some outside the node box
    diameters[t] = t % 100 == 3 ? 2.0 : small(rng); // five long ones
  }
  for (Vec3& x : nodes)
    x = {u(rng), u(rng), u(rng)};
  const NearLists near = find_near_triangles(nodes, centroids, diameters, far_ratio);
  for (size_t i = 0; i < nodes.size(); ++i) {
    std::vector<int> found(near.triangle.begin() + near.offset[i],
                           near.triangle.begin() + near.offset[i + 1]),
        expected;
    for (size_t t = 0; t < centroids.size(); ++t)
      if (norm(nodes[i] - centroids[t]) < far_ratio * diameters[t])
        expected.push_back(int(t));
    std::sort(found.begin(), found.end());
    CHECK(found == expected);
  }
}
