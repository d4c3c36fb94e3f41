#pragma once
// One home for the set-up of the periodic sums: the method, and the choice of xi, the
// cut-offs and the Spectral-Ewald grid from one tolerance. A run, `capsim bench` and the
// backend self-test all build their box here.
#include "common/choice.hpp"
#include "stokes/ewald/spectral_ewald.hpp"
#include "stokes/kernels/periodic_stokeslet.hpp"
#include "stokes/single_layer/periodic_single_layer.hpp"

#include <cmath>
#include <string>

namespace capsim {

// How the reciprocal (smooth) part of the periodic sum is taken: Spectral Ewald (FFTs on
// a grid), directly over the quadrature points (plain Ewald, the reference), or directly
// over multipole patches (the paper's coarse graining, section 3.1).
enum class EwaldMethod { spectral, direct, patches };

// The names of the method key (and `capsim bench --method`), written once.
inline constexpr Choice<EwaldMethod> kEwaldMethods[] = {
    {"spectral", EwaldMethod::spectral},
    {"direct", EwaldMethod::direct},
    {"patches", EwaldMethod::patches}};

EwaldMethod parse_ewald_method(const std::string& name); // throws std::invalid_argument
std::string to_string(EwaldMethod m);

// The periodic box of a suspension: a cube of side L sheared with the flow (Lees-Edwards:
// the lattice strain offset is shear_rate * t). L = 0 means unbounded fluid.
struct PeriodicBox {
  double L = 0;
  EwaldMethod method = EwaldMethod::spectral;
  EwaldParameters ewald;
  // The double layer's (lambda != 1; stokes/double_layer/periodic_double_layer.hpp), at
  // the same tolerance: with method spectral its Spectral-Ewald sums (double_layer_grid,
  // the stresslet's own support) at their xi of least modelled cost, otherwise plain
  // Ewald sums at theirs.
  EwaldParameters double_layer;
  SpectralParameters double_layer_grid; // method spectral
  // Method spectral: the split and grid of the double layer's self matrices (one grid
  // pass per capsule; PeriodicDoubleLayer), at kSelfMatrixXiFactor of its xi.
  EwaldParameters double_layer_self;
  SpectralParameters double_layer_self_grid;
  SpectralParameters grid; // method spectral: its grid
  int patch_level = 1;     // method patches: patches are the faces of this level
};

// The precision of a stage of the periodic sums (the Spectral-Ewald grids and FFTs, the
// real-space sum): double, single, or automatic (single where the tolerance is at least
// kSinglePrecisionTolerance).
enum class Precision { double_precision, single_precision, automatic };

Precision parse_precision(const std::string& name); // throws invalid_argument
std::string to_string(Precision p);

// Single precision rounds the velocities by about 3e-7 of themselves (the grids) and 1e-7
// (the real-space sum; rms, measured: docs/performance.md, "Single precision"); from this
// tolerance on that is at most a thirtieth of the requested error.
constexpr double kSinglePrecisionTolerance = 1e-5;

// The precision a stage runs in: p where given; for automatic, single where the tolerance
// is at least kSinglePrecisionTolerance and `available` (the evaluating backend has it),
// else double. The one rule for `auto`: the run plan, bench and the box all apply it.
Precision resolve_precision(Precision p, double tolerance, bool available = true);

// What a run asks of the periodic sums: the one type from the run's options
// (config/run_options.hpp: method, ewald.*) to the box.
struct EwaldOptions {
  EwaldMethod method = EwaldMethod::spectral;
  double tolerance = 1e-6; // truncation tolerance of the real and reciprocal sums
  double xi = 0;           // splitting parameter; <= 0: automatic
  int patch_level = 1;     // method patches: patches = faces of this icosphere level
  Precision precision = Precision::automatic;            // method spectral: its grids
  Precision real_space_precision = Precision::automatic; // the real-space sum (CPU)
};

// The box of side L for `options`: xi as given, or (xi <= 0) the one of least modelled
// cost for `nodes` targets and `points` quadrature points, raised where needed to keep
// r_cut below max_cut_fraction L (a backend's limit); then the cut-offs and, for
// spectral, the grid.
PeriodicBox make_periodic_box(double L, const EwaldOptions& options, long nodes,
                              long points, double max_cut_fraction = INFINITY);

// The reciprocal-sum selection of periodic_single_layer_velocity for this box, with the
// Spectral-Ewald state (null unless the method is spectral).
ReciprocalSum reciprocal_sum(const PeriodicBox& box, SpectralEwald* spectral);

} // namespace capsim
