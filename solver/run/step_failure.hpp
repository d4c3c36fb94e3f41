#pragma once
// A fault of the state after a step (dynamics/state_checks.hpp) as the error that stops
// the run, with what to do about it in terms of the run's keys.
#include "dynamics/lees_edwards.hpp"
#include "dynamics/state_checks.hpp"
#include "membrane/membrane_forces.hpp"

#include <vector>

namespace capsim {

// Throws SimulationError (a numerical failure at `time`) when find_fault finds a fault,
// with what to do about it: for an inverted triangle next to compressed elements
// (membrane/compression.hpp) the membrane buckled, and the message says so and what
// regularises it; otherwise the time step was too large.
void check_state(const Membrane& membrane, int num_capsules, const std::vector<Vec3>& x,
                 double time, double max_extent = 10.0);

// Throws SimulationError of kind "contact" when nodes of two capsules, or of a capsule
// and its periodic image, come closer than stop_distance (suspension.stop_distance) at
// `time`: capsules may not interpenetrate.
void check_contact(const Topology& topo, int num_capsules, const ShearedLattice& lattice,
                   const std::vector<Vec3>& x, double stop_distance, double time);

} // namespace capsim
