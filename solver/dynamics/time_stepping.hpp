#pragma once
// What the time loop does around each step (paper eq. 3.2; the step itself is
// Flow::heun_step): Freund's (2007) volume constraint, the checks that stop a broken
// run, and the automatic step size.
#include "dynamics/simulation_error.hpp"
#include "membrane/membrane_forces.hpp"
#include "mesh/icosphere.hpp"

#include <string>
#include <vector>

namespace capsim {

// Moves each capsule's nodes along their normals by (V0 - V)/A until the relative volume
// error is below 1e-13 (three or four passes). Returns each capsule's (V - V0)/V0 found
// before correcting: the volume drift of the step that is being corrected.
std::vector<double> enforce_volume(const Topology& topo, int num_capsules,
                                   std::vector<Vec3>& x,
                                   const std::vector<double>& volume0);

// Removes from the node velocities u of each capsule the rate of change of its enclosed
// volume: u_i <- u_i - r n_i along the unit node normals n_i, with r such that
// dV/dt = sum_i dV/dx_i . u_i = 0 (dV/dx_i = 1/6 of the node's summed area vectors). The
// boundary-element velocity changes the discrete volume at a rate set by the mesh
// (about 0.4 % per unit strain at level 2); enforce_volume alone removes that drift after
// each step, a splitting whose global error is first order in dt whatever the scheme.
// Applied to every stage's velocity, the scheme integrates a volume-preserving field at
// its own order and enforce_volume removes only the O(dt^3) rest (docs/method.md).
void remove_volume_rate(const Topology& topo, int num_capsules,
                        const std::vector<Vec3>& x, std::vector<Vec3>& u);

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

// Throws SimulationError (a numerical failure at `time`) when find_fault finds a fault,
// with what to do about it: for an inverted triangle next to compressed elements
// (membrane/compression.hpp) the membrane buckled, and the message says so and what
// regularises it; otherwise the time step was too large.
void check_state(const Membrane& membrane, int num_capsules, const std::vector<Vec3>& x,
                 double time, double max_extent = 10.0);

// The guard at a kernel's input or output: throws SimulationError naming `what` (e.g.
// "membrane traction"), the capsule and the node of the first value of v that is NaN
// or Inf, so that such a value stops the run at once instead of spreading into every
// node and the averages.
void require_finite(const std::vector<Vec3>& v, int nodes_per_capsule,
                    const std::string& what, double time);

// The automatic step: dt = safety * Ca * h, h the mean edge length of the undeformed
// mesh. The membrane's fastest relaxation mode on scale h has rate ~ Gs/(mu h) = 1/(Ca
// h), so an explicit scheme needs dt = O(Ca h) (safety 0.5 was stable at levels 2 and
// 3 for Ca 0.03-0.6, docs/method.md). A bending modulus eb = kb / (Gs a^2) adds modes of
// rate ~ Gs eb / (mu h^3): alone they allow dt up to about 0.2 Ca h^3 / eb (measured on a
// relaxing capsule at levels 2 and 3), so the step becomes safety * Ca * h / (1 + 4 eb /
// h^2), which tends to 0.125 Ca h^3 / eb at safety 0.5.
double automatic_time_step(double ca, double mean_edge, double safety,
                           double bending = 0);

} // namespace capsim
