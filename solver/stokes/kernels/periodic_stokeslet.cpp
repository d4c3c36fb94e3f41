#include "stokes/kernels/periodic_stokeslet.hpp"

#include "stokes/kernels/ewald_kernel.hpp"
#include "stokes/kernels/stokeslet.hpp"

#include <cmath>
#include <stdexcept>

namespace capsim {
namespace {

// Smallest x on a 1e-3 grid with decay(x) <= tol (decay is decreasing beyond its peak).
template <class Decay> double solve_decay(Decay decay, double tol) {
  double x = 0.5;
  while (decay(x) > tol)
    x += 1e-3;
  return x;
}

void add_column(Mat3& m, int j, Vec3 v) {
  m.m[0][j] += v.x;
  m.m[1][j] += v.y;
  m.m[2][j] += v.z;
}

const Vec3 kUnit[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

} // namespace

EwaldParameters choose_ewald_parameters(double L, double tolerance, double xi) {
  if (!(tolerance > 0 && tolerance < 1))
    throw std::invalid_argument("ewald tolerance must be in (0, 1)");
  EwaldParameters p;
  p.xi = xi > 0 ? xi : kSqrtPi / L;
  double xc = solve_decay(
      [](double x) {
        return std::erfc(x) + 4.0 / kSqrtPi * x * x * x * std::exp(-x * x);
      },
      tolerance);
  double qc = solve_decay([](double q) { return (1.0 + q + 2.0 * q * q) * std::exp(-q); },
                          tolerance);
  p.r_cut = xc / p.xi;
  p.k_cut = 2.0 * p.xi * std::sqrt(qc);
  return p;
}

double balanced_xi(double L, double tolerance, long targets, long sources,
                   double pair_cost) {
  EwaldParameters unit = choose_ewald_parameters(L, tolerance, 1.0);
  const double xc = unit.r_cut, qc = unit.k_cut * unit.k_cut / 4.0, v = L * L * L;
  const double t = double(targets), s = double(sources);
  double xi6 = pair_cost * t * s * kPi * kPi * kPi * xc * xc * xc /
               ((t + s) * v * v * std::pow(qc, 1.5));
  return std::max(std::pow(xi6, 1.0 / 6.0), kSqrtPi / L);
}

std::vector<Vec3> wave_vectors(const ShearedLattice& g, double k_cut) {
  std::vector<Vec3> ks;
  for_each_wave_vector(g, k_cut, [&](int, int, int, Vec3 k) { ks.push_back(k); });
  return ks;
}

Mat3 periodic_stokeslet(const ShearedLattice& g, Vec3 r, const EwaldParameters& p,
                        EwaldCounts* counts) {
  Mat3 j;
  EwaldCounts n;
  const Vec3 r0 = wrap_to_cell(g, r); // J^E is periodic: sum around the nearest image
  if (norm(r0) < 1e-12 * g.L)
    throw std::invalid_argument("the periodic Stokeslet is singular at lattice points");
  const int nr = int(std::ceil(p.r_cut / g.L)) + 1;
  for (int n3 = -nr; n3 <= nr; ++n3)
    for (int n2 = -nr; n2 <= nr; ++n2)
      for (int m1 = -nr - 1; m1 <= nr + 1; ++m1) {
        // x of the image is L (n1 + s n2): centre the n1 range on -s n2.
        const double n1 = m1 + std::round(-g.s * n2);
        Vec3 rn = r0 + lattice_point(g, n1, n2, n3);
        if (norm(rn) >= p.r_cut)
          continue;
        for (int c = 0; c < 3; ++c)
          add_column(j, c, ewald_real_apply(rn, kUnit[c], p.xi));
        ++n.images;
      }
  const double volume = g.L * g.L * g.L;
  for (const Vec3& k : wave_vectors(g, p.k_cut)) {
    double c = 8.0 * kPi / volume * std::cos(dot(k, r0));
    for (int col = 0; col < 3; ++col)
      add_column(j, col, c * ewald_recip_apply(k, kUnit[col], p.xi));
    ++n.wave_vectors;
  }
  if (counts)
    *counts = n;
  return j;
}

} // namespace capsim
