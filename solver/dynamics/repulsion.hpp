#pragma once
// Optional short-range repulsion between the nodes of different capsules (off by
// default; not in the paper; not between a capsule and its own periodic image, which
// only a box little wider than a capsule brings close: the contact check stops that).
// Where two membranes come closer than the mesh can resolve, the lubrication flow
// between them is under-resolved and nodes may cross; a pair potential that acts only
// within `range` keeps the gap open. Each pair of nodes i, j of different capsules at
// distance d < range has the energy
//   E(d) = (force range / 3) (1 - d/range)^3,
// a repulsive force of magnitude force (1 - d/range)^2: zero with zero slope at the edge
// of the range, `force` at contact. Units: lengths in a, forces in mu gammadot a^2 (the
// solver's unit; the flow that presses two capsules together scales with it, so one
// setting serves every Ca).
#include "common/vec3.hpp"
#include "stokes/cells/sheared_lattice.hpp"

#include <vector>

namespace capsim {

struct RepulsionOptions {
  double range = 0.1; // in a
  double force = 0.0; // at contact, in mu gammadot a^2; 0 = off
  bool on() const { return force > 0 && range > 0; }
};

// Adds dE/dx of every node pair to grad (x: num_capsules blocks of nodes_per_capsule
// nodes, periodic in g) and counts, per capsule, the nodes with at least one partner
// within range (`repelled`, resized to the number of capsules; may be null).
void add_repulsion_gradient(const ShearedLattice& g, int nodes_per_capsule,
                            const std::vector<Vec3>& x, const RepulsionOptions& r,
                            std::vector<Vec3>& grad,
                            std::vector<int>* repelled = nullptr);

} // namespace capsim
