#pragma once
// Where a membrane is compressed: the elements whose minor principal tension T2 of the
// paper's energy (eq. 2.10) is compressive. A membrane without bending stiffness buckles
// under any compressive tension, at the element scale on a mesh (Lac et al. 2004), which
// is how a strongly stretched capsule folds until a triangle inverts
// (docs/suspensions.md); with membrane.wrinkling these are the elements that wrinkle.
#include "membrane/neo_hookean.hpp"
#include "mesh/icosphere.hpp"

#include <vector>

namespace capsim {

// T2 / Gs below which an element counts as compressed. Not zero: T2 is zero but for
// round-off (and the volume constraint's 1e-13 corrections) in a relaxed capsule, and
// the threshold stays a thousandth of the tensions that deform a capsule at Ca 0.05-0.6
// (0.1-1 Gs) and of the compression at a fold (T2 -1.1 to -1.4 Gs).
inline constexpr double kCompressedTension = -1e-3;

struct Compression {
  int elements = 0;       // elements with T2 < kCompressedTension
  int of = 0;             // elements looked at
  double min_tension = 0; // the smallest T2 over Gs among them (0 when none)
};

// Over all the elements of `tensions`.
Compression compression(const std::vector<ElementTensions>& tensions);

// Over the elements that share a node with `triangle` (itself included).
Compression compression_near(const Topology& topo,
                             const std::vector<ElementTensions>& tensions, int triangle);

} // namespace capsim
