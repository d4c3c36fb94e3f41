#include "stokes/kernels/ewald_kernel.hpp"
#include "stokes/kernels/periodic_stokeslet.hpp"
#include "stokes/kernels/stokeslet.hpp"

#include <catch2/catch.hpp>

using namespace capsim;

namespace {
double max_abs_diff(const Mat3& a, const Mat3& b) {
  double d = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      d = std::max(d, std::abs(a.m[i][j] - b.m[i][j]));
  return d;
}
double max_abs(const Mat3& a) {
  return max_abs_diff(a, Mat3{});
}
} // namespace

TEST_CASE("ewald: the periodic Stokeslet does not depend on xi", "[ewald]") {
  const double L = 4.0;
  for (double strain : {0.0, 0.3, -0.5}) {
    ShearedLattice g = make_sheared_lattice(L, strain);
    const Vec3 r{0.7, -1.3, 0.4};
    const double xi0 = kSqrtPi / L;
    Mat3 ref = periodic_stokeslet(g, r, choose_ewald_parameters(L, 1e-15, xi0));
    for (double factor : {0.6, 1.7}) {
      Mat3 j = periodic_stokeslet(g, r, choose_ewald_parameters(L, 1e-15, factor * xi0));
      INFO("strain " << strain << " xi factor " << factor);
      CHECK(max_abs_diff(j, ref) / max_abs(ref) < 1e-10);
    }
  }
}

TEST_CASE("ewald: strains s and s + 1 give the same lattice and kernel", "[ewald]") {
  const double L = 3.0;
  EwaldParameters p = choose_ewald_parameters(L, 1e-13);
  const Vec3 r{0.2, 0.9, -0.6};
  Mat3 a = periodic_stokeslet(make_sheared_lattice(L, 0.3), r, p);
  Mat3 b = periodic_stokeslet(make_sheared_lattice(L, 1.3), r, p);
  Mat3 c = periodic_stokeslet(make_sheared_lattice(L, -0.7), r, p);
  CHECK(max_abs_diff(a, b) / max_abs(a) < 1e-12);
  CHECK(max_abs_diff(a, c) / max_abs(a) < 1e-12);
}

TEST_CASE("ewald: the kernel is periodic on the sheared lattice and symmetric",
          "[ewald]") {
  const double L = 3.0;
  ShearedLattice g = make_sheared_lattice(L, 0.25);
  EwaldParameters p = choose_ewald_parameters(L, 1e-13);
  const Vec3 r{0.5, -0.4, 1.1};
  Mat3 j = periodic_stokeslet(g, r, p);
  for (Vec3 shift : {lattice_point(g, 1, 0, 0), lattice_point(g, 0, 1, 0),
                     lattice_point(g, 2, -1, 1)}) {
    Mat3 js = periodic_stokeslet(g, r + shift, p);
    CHECK(max_abs_diff(j, js) / max_abs(j) < 1e-11);
  }
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      CHECK(j.m[a][b] == Approx(j.m[b][a]).margin(1e-13));
  // J^E(-r) = J^E(r): the lattice is centrosymmetric.
  CHECK(max_abs_diff(j, periodic_stokeslet(g, -1.0 * r, p)) / max_abs(j) < 1e-12);
}

TEST_CASE("ewald: near a source the kernel is the free Stokeslet plus a smooth part",
          "[ewald]") {
  // For a box much larger than r, J^E(r) - J(r) is bounded as r -> 0 (the images and the
  // k = 0 removal add only a smooth field), so halving r leaves the difference unchanged.
  const double L = 10.0;
  ShearedLattice g = make_sheared_lattice(L, 0.0);
  EwaldParameters p = choose_ewald_parameters(L, 1e-13);
  auto smooth_part = [&](double scale) {
    Vec3 r = scale * Vec3{0.3, 0.2, -0.1};
    Mat3 j = periodic_stokeslet(g, r, p), d;
    for (int c = 0; c < 3; ++c) {
      Vec3 f{c == 0 ? 1.0 : 0.0, c == 1 ? 1.0 : 0.0, c == 2 ? 1.0 : 0.0};
      Vec3 free = stokeslet_apply(r, f);
      d.m[0][c] = j.m[0][c] - free.x;
      d.m[1][c] = j.m[1][c] - free.y;
      d.m[2][c] = j.m[2][c] - free.z;
    }
    return d;
  };
  Mat3 a = smooth_part(1e-2), b = smooth_part(5e-3);
  CHECK(max_abs_diff(a, b) < 1e-3 * max_abs(a));
}

namespace {

// Velocity (without the -1/(8 pi) factor) of forces f_k at y_k: Ewald, or the direct sum
// over the images inside a sphere of radius R (spherical summation).
Vec3 ewald_velocity(const ShearedLattice& g, const EwaldParameters& p, Vec3 x,
                    const std::vector<Vec3>& y, const std::vector<Vec3>& f) {
  Vec3 v;
  for (size_t k = 0; k < y.size(); ++k) {
    Mat3 j = periodic_stokeslet(g, x - y[k], p);
    v += Vec3{j.m[0][0] * f[k].x + j.m[0][1] * f[k].y + j.m[0][2] * f[k].z,
              j.m[1][0] * f[k].x + j.m[1][1] * f[k].y + j.m[1][2] * f[k].z,
              j.m[2][0] * f[k].x + j.m[2][1] * f[k].y + j.m[2][2] * f[k].z};
  }
  return v;
}

Vec3 direct_velocity(const ShearedLattice& g, double radius, Vec3 x,
                     const std::vector<Vec3>& y, const std::vector<Vec3>& f) {
  Vec3 v;
  const int n = int(radius / g.L) + 2;
  for (int n3 = -n; n3 <= n; ++n3)
    for (int n2 = -n; n2 <= n; ++n2)
      for (int n1 = -2 * n; n1 <= 2 * n; ++n1) {
        Vec3 shift = lattice_point(g, n1, n2, n3);
        if (norm(shift) > radius)
          continue;
        for (size_t k = 0; k < y.size(); ++k)
          v += stokeslet_apply(x - y[k] + shift, f[k]);
      }
  return v;
}

} // namespace

TEST_CASE("ewald: matches a brute-force lattice sum for a force-neutral source set",
          "[ewald]") {
  // Spherical summation of a force-neutral set converges only up to a field linear in x
  // (the conditionally convergent dipole and quadrupole shells), which the Ewald sum
  // fixes by leaving out k = 0. Second differences in x remove that linear field, and
  // what remains of the direct sum converges like 1/R^2.
  const double L = 2.0;
  ShearedLattice g = make_sheared_lattice(L, 0.3);
  EwaldParameters p = choose_ewald_parameters(L, 1e-14);
  std::vector<Vec3> y = {{0.1, 0.2, -0.3}, {-0.4, 0.5, 0.2}, {0.3, -0.6, 0.1}};
  std::vector<Vec3> f = {{1.0, -0.5, 0.3}, {-0.4, 1.0, 0.2}, {-0.6, -0.5, -0.5}};
  const Vec3 x0{0.35, 0.1, 0.45}, h{0.15, -0.1, 0.05};
  auto second_difference = [&](auto velocity) {
    return velocity(x0 + h) - 2.0 * velocity(x0) + velocity(x0 - h);
  };
  Vec3 ewald = second_difference([&](Vec3 x) { return ewald_velocity(g, p, x, y, f); });
  Vec3 d20 =
      second_difference([&](Vec3 x) { return direct_velocity(g, 20 * L, x, y, f); });
  Vec3 d40 =
      second_difference([&](Vec3 x) { return direct_velocity(g, 40 * L, x, y, f); });
  INFO("ewald " << ewald.x << " " << ewald.y << " " << ewald.z);
  INFO("R=20L " << d20.x << " " << d20.y << " " << d20.z);
  INFO("R=40L " << d40.x << " " << d40.y << " " << d40.z);
  double e20 = norm(d20 - ewald) / norm(ewald), e40 = norm(d40 - ewald) / norm(ewald);
  CHECK(e40 < 2e-7);
  CHECK(e20 / e40 > 3.0); // the 1/R^2 convergence of the direct sum (4 for R -> 2R)
}
