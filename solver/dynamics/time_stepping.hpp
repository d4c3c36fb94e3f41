#pragma once
// Time integration of the membrane nodes (paper eq. 3.2): explicit 2nd-order Runge-Kutta
// (Heun) on dx/dt = v(x), then Freund's (2007) volume constraint.
#include "dynamics/repulsion.hpp"
#include "membrane/membrane_forces.hpp"
#include "stokes/periodic_stokeslet.hpp"
#include "stokes/single_layer.hpp"
#include "stokes/spectral_ewald.hpp"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace capsim {

// A run that cannot go on: a numerical failure (kind "numerical": NaN, blow-up, broken
// mesh) or two capsules in contact (kind "contact"). The run stops, the last good
// checkpoint stays, and summary.json records the kind as how the run ended.
struct SimulationError : std::runtime_error {
  explicit SimulationError(const std::string& what, std::string kind = "numerical")
      : std::runtime_error(what), kind(std::move(kind)) {}
  std::string kind;
};

// The periodic box of a suspension: a cube of side L sheared with the flow (Lees-Edwards:
// the lattice strain offset is shear_rate * t). L = 0 means unbounded fluid.
struct PeriodicBox {
  double L = 0;
  EwaldParameters ewald;
  bool spectral = false;   // reciprocal sums by Spectral Ewald (else directly)
  SpectralParameters grid; // its grid, when spectral
  int patch_level = -1;    // >= 0: direct reciprocal sums over multipole patches
};

// The box of side L for `method` (spectral | direct | patches) at `tolerance`: xi as
// given, or (xi <= 0) chosen for speed from the numbers of target nodes and source
// points; patch_level: the patches' icosphere level for method patches.
PeriodicBox make_periodic_box(double L, const std::string& method, double tolerance,
                              double xi, long nodes, long points, int patch_level = -1);

// Where the velocity field is evaluated: the CPU (OpenMP), or a CUDA device
// (cuda/device_flow.hpp) with the data resident there between steps.
enum class Backend { cpu, cuda };

Backend parse_backend(const std::string& name); // throws std::invalid_argument
std::string to_string(Backend b);

class DeviceFlow;

// The velocity field of M capsules in simple shear v_inf = (shear_rate y, 0, 0)
// (shear_rate = 0: quiescent fluid), unbounded or in a sheared periodic box.
class CapsuleFlow {
public:
  CapsuleFlow(const Membrane& membrane, int num_capsules, double shear_rate,
              LoadMapping load, QuadratureOptions quadrature, PeriodicBox box = {},
              Backend backend = Backend::cpu);

  // The traction jump q at the nodes (capsule after capsule) at positions x and time t:
  // the membrane load, plus the repulsion between capsules when it is on.
  void traction(const std::vector<Vec3>& x, double t, std::vector<Vec3>& q) const;

  // Short-range repulsion between capsules (periodic box, CPU backend only).
  void set_repulsion(const RepulsionOptions& r);
  // Adds the repulsion's dE/dx at (x, t) to grad when it is on; returns, per capsule,
  // the nodes within its range of another capsule (zeros when off).
  std::vector<int> add_repulsion(const std::vector<Vec3>& x, double t,
                                 std::vector<Vec3>& grad) const;

  // Node velocities u at positions x and time t (the time sets the lattice strain).
  void velocity(const std::vector<Vec3>& x, double t, std::vector<Vec3>& u) const;

  // dW/dx of all capsules (capsule after capsule) and the energy of each.
  std::vector<double> energy_gradient(const std::vector<Vec3>& x,
                                      std::vector<Vec3>& grad) const;

  bool periodic() const { return box_.L > 0; }
  ShearedLattice lattice(double t) const {
    return make_sheared_lattice(box_.L, shear_rate_ * t);
  }
  const Membrane& membrane() const { return membrane_; }
  int num_capsules() const { return num_capsules_; }
  Backend backend() const { return device_ ? Backend::cuda : Backend::cpu; }
  // The device evaluation when the backend is cuda, else null.
  DeviceFlow* device() const { return device_.get(); }

private:
  const Membrane& membrane_;
  int num_capsules_;
  double shear_rate_;
  LoadMapping load_;
  QuadratureOptions quadrature_;
  PeriodicBox box_;
  RepulsionOptions repulsion_;              // off unless set
  std::shared_ptr<SpectralEwald> spectral_; // FFT plans and grids, made once
  std::shared_ptr<DeviceFlow> device_;      // the cuda backend's state, when selected
};

// One Heun step from time t (on the flow's backend): x* = x + dt u(x, t); x <- x + dt/2
// (u(x, t) + u(x*, t + dt)).
void rk2_step(const CapsuleFlow& flow, std::vector<Vec3>& x, double t, double dt);

// Moves each capsule's nodes along their normals by (V0 - V)/A until the relative volume
// error is below 1e-13 (three or four passes). Returns each capsule's (V - V0)/V0 found
// before correcting: the volume drift of the step that is being corrected.
std::vector<double> enforce_volume(const Topology& topo, int num_capsules,
                                   std::vector<Vec3>& x,
                                   const std::vector<double>& volume0);

// Throws SimulationError if any position is not finite, a capsule has stretched beyond
// max_extent radii from its centroid, or a triangle has collapsed or inverted.
void check_state(const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
                 double time, double max_extent = 10.0);

// The automatic step: dt = safety * Ca * h, h the mean edge length of the undeformed
// mesh. The membrane's fastest relaxation mode on scale h has rate ~ Gs/(mu h) = 1/(Ca
// h), so an explicit scheme needs dt = O(Ca h) (DESIGN.md 2; safety 0.5 was stable
// there). A bending modulus eb = kb / (Gs a^2) adds modes of rate ~ Gs eb / (mu h^3):
// alone they allow dt up to about 0.2 Ca h^3 / eb (measured on a relaxing capsule at
// levels 2 and 3), so the step becomes safety * Ca * h / (1 + 4 eb / h^2), which tends to
// 0.125 Ca h^3 / eb at safety 0.5.
double automatic_time_step(double ca, double mean_edge, double safety,
                           double bending = 0);

} // namespace capsim
