#include "dynamics/packing.hpp"

#include "common/constants.hpp"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace capsim {
namespace {

Vec3 minimum_image(Vec3 d, double box) {
  auto w = [box](double v) { return v - box * std::round(v / box); };
  return {w(d.x), w(d.y), w(d.z)};
}

Vec3 wrap_into_box(Vec3 p, double box) {
  auto w = [box](double v) { return v - box * std::floor(v / box); };
  return {w(p.x), w(p.y), w(p.z)};
}

// One sweep over all pairs: every pair closer than d is pushed apart symmetrically to
// 1.001 d (a margin relative to d, so that clusters of touching spheres separate in a few
// sweeps instead of creeping towards contact). Returns the largest overlap found.
double relax_sweep(std::vector<Vec3>& c, double box, double d) {
  double worst = 0;
  for (size_t i = 0; i < c.size(); ++i)
    for (size_t j = i + 1; j < c.size(); ++j) {
      Vec3 r = minimum_image(c[j] - c[i], box);
      double dist = norm(r);
      if (dist >= d)
        continue;
      worst = std::max(worst, d - dist);
      Vec3 dir = dist > 1e-12 ? (1.0 / dist) * r : Vec3{1, 0, 0};
      Vec3 push = (0.5 * (1.001 * d - dist)) * dir;
      c[i] = wrap_into_box(c[i] - push, box);
      c[j] = wrap_into_box(c[j] + push, box);
    }
  return worst;
}

} // namespace

double min_pair_distance(const std::vector<Vec3>& c, double box) {
  double best = INFINITY;
  for (size_t i = 0; i < c.size(); ++i)
    for (size_t j = i + 1; j < c.size(); ++j)
      best = std::min(best, norm(minimum_image(c[j] - c[i], box)));
  return best;
}

std::vector<Vec3> pack_spheres(const PackingOptions& o) {
  const double d_final = 2.0 + o.min_gap;
  const double phi_eff =
      o.capsules * kPi * d_final * d_final * d_final / 6.0 / (o.box * o.box * o.box);
  if (phi_eff > 0.6)
    throw std::runtime_error(
        "cannot pack " + std::to_string(o.capsules) + " capsules with a gap of " +
        std::to_string(o.min_gap) + " a into a box of side " + std::to_string(o.box) +
        ": the volume fraction including the gap would be " + std::to_string(phi_eff) +
        " (at most 0.6 is possible for a random packing); lower phi or the gap");
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u(0.0, o.box);
  std::vector<Vec3> c(o.capsules);
  for (auto& p : c)
    p = {u(rng), u(rng), u(rng)};
  double d = 0.5 * d_final;
  int sweeps = 0;
  while (true) {
    while (relax_sweep(c, o.box, d) > 0)
      if (++sweeps > o.max_sweeps)
        throw std::runtime_error(
            "packing did not converge at diameter " + std::to_string(d) + " after " +
            std::to_string(o.max_sweeps) + " sweeps; lower phi or the gap");
    if (d >= d_final)
      return c;
    d = std::min(d_final, d * 1.01);
  }
}

} // namespace capsim
