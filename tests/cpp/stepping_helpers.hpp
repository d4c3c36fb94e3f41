#pragma once
// A shared check of the time-scheme tests: whether a stepper stays bounded.
#include "dynamics/time_schemes.hpp"
#include "dynamics/volume_constraint.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace capsim::testing {

// Steps x from t = 0 `steps` times by dt, restoring the volumes v0 after each step;
// whether every node stayed finite and within 10 a of the origin throughout (it stops at
// the first step that left them).
inline bool stays_bounded(Stepper& stepper, const Topology& topo, int num_capsules,
                          std::vector<Vec3>& x, const std::vector<double>& v0, double dt,
                          int steps) {
  for (int step = 0; step < steps; ++step) {
    stepper.step(x, step * dt, dt);
    enforce_volume(topo, num_capsules, x, v0);
    for (const Vec3& p : x)
      if (!std::isfinite(p.x) || !(norm(p) < 10))
        return false;
  }
  return true;
}

// Steps x from t = 0 `steps` times by dt, restoring the volumes v0 after each step.
inline void advance(Stepper& stepper, const Topology& topo, int num_capsules,
                    std::vector<Vec3>& x, const std::vector<double>& v0, double dt,
                    int steps) {
  for (int step = 0; step < steps; ++step) {
    stepper.step(x, step * dt, dt);
    enforce_volume(topo, num_capsules, x, v0);
  }
}

// The largest distance between corresponding nodes of a and b.
inline double largest_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i)
    e = std::max(e, norm(a[i] - b[i]));
  return e;
}

} // namespace capsim::testing
