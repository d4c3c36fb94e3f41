#pragma once
// A shared check of the time-scheme tests: whether a stepper stays bounded.
#include "dynamics/time_schemes.hpp"
#include "dynamics/volume_constraint.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace capsim::testing {

// One step of x from t by dt, restoring the volumes v0 after it.
inline void step_once(Stepper& stepper, const Topology& topo, int num_capsules,
                      std::vector<Vec3>& x, const std::vector<double>& v0, double t,
                      double dt) {
  stepper.step(x, t, dt);
  enforce_volume(topo, num_capsules, x, v0);
}

// Steps x from t = 0 `steps` times by dt (step_once); whether every node stayed finite
// and within 10 a of the origin throughout (it stops at the first step that left them).
inline bool stays_bounded(Stepper& stepper, const Topology& topo, int num_capsules,
                          std::vector<Vec3>& x, const std::vector<double>& v0, double dt,
                          int steps) {
  for (int step = 0; step < steps; ++step) {
    step_once(stepper, topo, num_capsules, x, v0, step * dt, dt);
    for (const Vec3& p : x)
      if (!std::isfinite(p.x) || !(norm(p) < 10))
        return false;
  }
  return true;
}

// Steps x from t = 0 `steps` times by dt (step_once).
inline void advance(Stepper& stepper, const Topology& topo, int num_capsules,
                    std::vector<Vec3>& x, const std::vector<double>& v0, double dt,
                    int steps) {
  for (int step = 0; step < steps; ++step)
    step_once(stepper, topo, num_capsules, x, v0, step * dt, dt);
}

// The largest distance between corresponding nodes of a and b.
inline double largest_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double e = 0;
  for (size_t i = 0; i < a.size(); ++i)
    e = std::max(e, norm(a[i] - b[i]));
  return e;
}

} // namespace capsim::testing
