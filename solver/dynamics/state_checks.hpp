#pragma once
// The checks that stop a broken run: faults of the node positions after a step, and
// values that are not finite at a kernel's input or output. What to do about a fault
// names configuration keys, so it is said where they are known (run/step_failure.hpp).
#include "dynamics/simulation_error.hpp"
#include "mesh/icosphere.hpp"

#include <string>
#include <vector>

namespace capsim {

// The first fault of positions x: a position is not finite, a capsule has stretched
// beyond max_extent radii from its centroid, or a triangle has collapsed or inverted.
struct StateFault {
  int capsule = -1;  // -1: no fault
  int triangle = -1; // the inverted triangle of that capsule, else -1
  std::string what;  // "a surface triangle has inverted", ...
};
StateFault find_fault(const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
                      double max_extent = 10.0);

// The fault as text ("in capsule C: ..."), or "" when there is none.
std::string broken_state(const Topology& topo, int num_capsules,
                         const std::vector<Vec3>& x, double max_extent = 10.0);

// The guard at a kernel's input or output: throws SimulationError naming `what` (e.g.
// "membrane traction"), the capsule and the node of the first value of v that is NaN
// or Inf, so that such a value stops the run at once instead of spreading into every
// node and the averages.
void require_finite(const std::vector<Vec3>& v, int nodes_per_capsule,
                    const std::string& what, double time);

} // namespace capsim
