#pragma once
// Initial positions of M capsules (spheres of radius a = 1) in a periodic cubic box of
// side L, non-overlapping with a minimum surface gap, seeded. Random sequential addition
// jams near phi = 0.38, so the spheres are placed at random at a fraction of their final
// size and grown in steps, each followed by pushing overlapping pairs apart
// (grow-and-relax, docs/method.md); this reaches phi = 0.45 and beyond.
#include "common/vec3.hpp"

#include <vector>

namespace capsim {

struct PackingOptions {
  int capsules = 100;
  double box = 0;       // L
  double min_gap = 0.1; // smallest allowed surface gap between capsules, in a
  unsigned seed = 1;
  int max_sweeps = 200000; // relaxation sweeps before giving up
};

// Centres in [0, L)^3. Throws std::runtime_error with a clear message if the spheres do
// not fit (the volume fraction including the gap is above ~0.6, or relaxation fails).
std::vector<Vec3> pack_spheres(const PackingOptions& o);

// Smallest centre-to-centre distance under the periodic minimum image.
double min_pair_distance(const std::vector<Vec3>& centres, double box);

} // namespace capsim
