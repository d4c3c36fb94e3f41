#pragma once
// The velocity field of M capsules in simple shear v_inf = (shear_rate y, 0, 0)
// (shear_rate = 0: quiescent fluid), unbounded or in a sheared periodic box, as the time
// loop sees it: the traction jump, the node velocities and a time step. Implemented on
// the CPU (dynamics/cpu_flow.hpp) and on a CUDA device (cuda/device_flow.hpp); one
// factory (run/flow_factory.hpp) checks a backend's capabilities against the set-up and
// builds it.
#include "common/choice.hpp"
#include "dynamics/repulsion.hpp"
#include "membrane/membrane_forces.hpp"
#include "stokes/double_layer/guess_history.hpp"
#include "stokes/ewald/ewald_setup.hpp"
#include "stokes/single_layer/periodic_single_layer.hpp"
#include "stokes/single_layer/single_layer.hpp"

#include <climits>
#include <cmath>
#include <string>
#include <vector>

namespace capsim {

// Where the velocity field is evaluated: the CPU (OpenMP) or one CUDA device.
enum class Backend { cpu, cuda };

// The names of the backend key, written once: the run key, its parsing and its printing.
inline constexpr Choice<Backend> kBackends[] = {{"cpu", Backend::cpu},
                                                {"cuda", Backend::cuda}};

Backend parse_backend(const std::string& name); // throws std::invalid_argument
std::string to_string(Backend b);

// What defines the flow, whichever backend evaluates it. The membrane is shared, not
// copied: it must outlive the flow.
struct FlowSetup {
  FlowSetup(const Membrane& membrane, int num_capsules = 1, double shear_rate = 1.0)
      : membrane(membrane), num_capsules(num_capsules), shear_rate(shear_rate) {}

  const Membrane& membrane;
  int num_capsules;
  double shear_rate;
  LoadMapping load = LoadMapping::lumped;
  QuadratureOptions quadrature;
  PeriodicBox box;            // box.L = 0: unbounded fluid
  RepulsionOptions repulsion; // between capsules in a periodic box; off by default
  // Viscosity ratio of the capsules' interior to the suspending fluid. At 1 the velocity
  // is u_inf + u_SL; otherwise the second-kind solution of
  // stokes/double_layer/second_kind_solve.hpp, in unbounded fluid or the periodic box.
  double lambda = 1.0;
  // lambda != 1: GMRES stops at this residual relative to the right-hand side, from the
  // first guess gmres_guess makes of the earlier evaluations' solutions.
  double gmres_tolerance = 1e-6;
  GmresGuess gmres_guess = GmresGuess::extrapolated;
};

// What a backend can evaluate. Declared once per backend, checked once by the factory.
struct FlowCapabilities {
  bool consistent_load = true;          // membrane.load: consistent (a mass-matrix solve)
  bool bending = true;                  // membrane.bending > 0
  bool drop = true;                     // membrane.law: drop (surface tension)
  bool repulsion = true;                // suspension.repulsion_force > 0
  bool direct_sums = true;              // methods direct and patches
  double max_cut_fraction = INFINITY;   // r_cut must stay below this fraction of L
  int max_spread_support = INT_MAX;     // Spectral-Ewald support P at most this
  bool single_grids = true;             // ewald.precision single (grids and FFTs)
  bool single_real_space = true;        // ewald.real_space_precision single
  bool viscosity_ratio = true;          // lambda != 1 in unbounded fluid (phi = 0)
  bool periodic_viscosity_ratio = true; // lambda != 1 in a periodic box
};

// The second-kind solves of lambda != 1 (none at lambda = 1): GMRES iterations per
// evaluation and the worst relative residual reached, for summary.json.
struct SecondKindStats {
  long solves = 0;
  long iterations = 0; // summed over the solves
  int max_iterations = 0;
  double max_residual = 0;
};

// Wall seconds in the stages of the flow's evaluations, accumulated while a profile is
// attached (`capsim run --profile`): what one step costs where, in situ. The CPU backend
// fills every field; another backend only the totals.
struct FlowProfile {
  long evaluations = 0;
  double velocity = 0;           // all of velocity()
  double traction = 0;           // membrane load (and repulsion), of velocity()
  double unbounded = 0;          // the free-space single layer (one capsule, phi = 0)
  PeriodicTimings periodic;      // the Ewald stages: set-up, near, real space, reciprocal
  double double_layer_setup = 0; // lambda != 1: the double layer set up for each solve
  double double_layer_apply = 0; // and applied, once per GMRES iteration (and residual)
  double volume_rate = 0;        // removing each capsule's volume rate from u
};

class Flow {
public:
  explicit Flow(const FlowSetup& setup) : setup_(setup) {}
  virtual ~Flow() = default;
  Flow(const Flow&) = delete;
  Flow& operator=(const Flow&) = delete;

  virtual Backend backend() const = 0;

  // The traction jump q at the nodes (capsule after capsule) at positions x and time t:
  // the membrane load, plus the repulsion between capsules when it is on.
  virtual void traction(const std::vector<Vec3>& x, double t,
                        std::vector<Vec3>& q) const = 0;

  // Node velocities u at positions x and time t (the time sets the lattice strain):
  // evaluate_velocity() of the backend, counted and timed into an attached profile.
  void velocity(const std::vector<Vec3>& x, double t, std::vector<Vec3>& u) const;

  // The right-hand side the time schemes (dynamics/time_schemes.hpp) integrate: u with
  // each capsule's volume rate removed (remove_volume_rate,
  // dynamics/volume_constraint.hpp), of a drop's nodes only the normal part
  // (dynamics/normal_motion.hpp).
  void volume_preserving_velocity(const std::vector<Vec3>& x, double t,
                                  std::vector<Vec3>& u) const;

  // On the CPU for every backend (the diagnostics need them between steps):
  // dW/dx of all capsules (capsule after capsule), returning the energy of each;
  std::vector<double> energy_gradient(const std::vector<Vec3>& x,
                                      std::vector<Vec3>& grad) const;
  // adds the repulsion's dE/dx at (x, t) to grad when it is on, returning per capsule
  // the nodes within its range of another capsule (zeros when off).
  std::vector<int> add_repulsion(const std::vector<Vec3>& x, double t,
                                 std::vector<Vec3>& grad) const;

  // The second-kind solves so far (all zero at lambda = 1).
  virtual SecondKindStats second_kind_stats() const { return {}; }
  // What the outputs (samples, snapshots) evaluate: velocity() without changing what
  // later evaluations start from (lambda != 1: GMRES's first guess), so that the steps
  // do not depend on how often the outputs come.
  virtual void output_velocity(const std::vector<Vec3>& x, double t,
                               std::vector<Vec3>& u) const {
    velocity(x, t, u);
  }
  // Forgets what the evaluations so far leave to later ones (GMRES's first guess): at a
  // checkpoint, so that a run resumed there takes the steps of the unbroken run, bit for
  // bit (the guess is not in the checkpoint).
  virtual void forget_history() const {}

  // Accumulates the stages of every later evaluation into *p (nullptr: none).
  void attach_profile(FlowProfile* p) { profile_ = p; }

  const FlowSetup& setup() const { return setup_; }
  const Membrane& membrane() const { return setup_.membrane; }
  int num_capsules() const { return setup_.num_capsules; }
  bool periodic() const { return setup_.box.L > 0; }
  ShearedLattice lattice(double t) const {
    return make_sheared_lattice(setup_.box.L, setup_.shear_rate * t);
  }

protected:
  virtual void evaluate_velocity(const std::vector<Vec3>& x, double t,
                                 std::vector<Vec3>& u) const = 0;

  FlowSetup setup_;
  FlowProfile* profile_ = nullptr;
};

} // namespace capsim
