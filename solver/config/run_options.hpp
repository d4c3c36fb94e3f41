#pragma once
// Run options: one struct field per config key, and one table (run_options.cpp) that
// names every key, its default, its allowed range and its help text. Parsing, validation,
// the resolved run.yaml and `capsim params` all read that table, so they cannot drift
// apart.
#include "dynamics/repulsion.hpp"
#include "dynamics/time_schemes.hpp"
#include "membrane/membrane_forces.hpp"
#include "stokes/double_layer/guess_history.hpp"
#include "stokes/ewald/ewald_setup.hpp"
#include "stokes/single_layer/single_layer.hpp"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace capsim {

struct OutputOptions {
  double sample_interval = 0.05;    // strain between rows of timeseries.h5
  double checkpoint_interval = 1.0; // strain between checkpoints
  double snapshot_interval = 2.0;   // strain between mesh snapshots (0: none)
};

// The value of a tolerance given as 'auto' (run/automatic_settings.hpp resolves it).
inline constexpr double kAutomatic = -1;

struct TimeOptions {
  // heun, rkc (explicit) or imex (linearly implicit)
  TimeScheme scheme = TimeScheme::heun;
  int stages = 4;       // of rkc
  double tolerance = 0; // largest step error (error_norm), in a; 0 = a fixed step
  ErrorNorm error_norm = ErrorNorm::max; // of the node errors: max or rms (per capsule)
};

struct SuspensionOptions {
  double min_gap = 0.1;        // smallest surface gap between capsules at t = 0, in a
  double stop_distance = 0.02; // stop when nodes of two capsules come this close, in a
  RepulsionOptions repulsion;  // between capsules; off by default
};

struct RunOptions {
  double ca = 0.2;               // capillary number mu gammadot a / Gs
  double phi = 0.0;              // volume fraction; 0 = one capsule in unbounded shear
  double lambda = 1.0;           // viscosity ratio interior / exterior
  double gmres_tolerance = 1e-6; // lambda != 1: GMRES's relative residual
  GmresGuess gmres_guess = GmresGuess::extrapolated; // lambda != 1: its first guess
  int capsules = 1;                                  // capsules per periodic box
  int mesh_level = 3;           // icosphere level: 2, 3, 4 = 320, 1280, 5120 triangles
  double dt = 0.0;              // time step in strain units; 0 = automatic ("auto")
  double dt_safety = 1.0;       // C in the automatic step dt = C Ca h (limit ~1.5)
  double dt_lambda_max = 1.0;   // lambda > 1: the automatic step's most growth
  TimeOptions time;             // scheme and adaptive step
  double t_end = 20.0;          // end of the run, gammadot t
  double t_avg_start = 10.0;    // start of the averaging window, gammadot t
  int seed = 1;                 // random seed (initial positions of suspensions)
  std::string flow = "shear";   // shear (v = (y, 0, 0)) or quiescent
  double initial_stretch = 1.0; // initial shape: x -> (s x, y/sqrt s, z/sqrt s)
  LoadMapping load = LoadMapping::lumped;
  MembraneLaw law = MembraneLaw::neo_hookean; // neo_hookean (the paper) or drop
  double bending = 0.0;   // bending modulus kb / (Gs a^2); 0 = none (the paper)
  bool wrinkling = false; // relaxed (tension-field) membrane energy; false = eq. 2.11
  QuadratureOptions quadrature;
  EwaldOptions ewald;
  SuspensionOptions suspension;
  OutputOptions output;
  int threads = 0;                // OpenMP threads; 0 = the OpenMP default
  Backend backend = Backend::cpu; // where the flow is evaluated: cpu or cuda (a GPU)
};

// Thrown for bad input; the message names the key and the allowed range.
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The allowed values of a number: from lo to hi, either end open or closed.
struct NumberRange {
  double lo, hi;
  bool lo_open = false, hi_open = false;
  bool contains(double v) const; // false for NaN
};
// "a number in (0, 10]", "an integer in [1, 5]".
std::string range_text(NumberRange r, bool integer);
// `text` quoted for an error message: control characters escaped, long text cut, so
// that the message stays one readable line.
std::string quoted_for_message(const std::string& text);
// The run keys' reading of numbers, for command-line options (bench, greens): "" when
// `text` is a finite number (an integer that fits an int, if `integer`), else
// "must be ..., got '...'".
std::string number_problem(const std::string& text, bool integer);
// Throws ConfigError "NAME: must be RANGE, got V" unless r holds v (never NaN).
void require_in(const std::string& name, double v, NumberRange r, bool integer = false);

// Reads a run file (YAML, nested maps allowed: `quadrature: {far_ratio: 4}` is the key
// quadrature.far_ratio), then applies `key=value` overrides, then validates everything.
RunOptions load_run_options(const std::string& yaml_path,
                            const std::vector<std::string>& overrides);
// The same from YAML text.
RunOptions parse_run_options(const std::string& yaml_text,
                             const std::vector<std::string>& overrides,
                             const std::string& source = "run file");
// The options stored in a checkpoint (all its build knew), then the overrides: a key
// added later takes the value every run took before it existed (kFormerValues in
// run_options.cpp), not today's default, so a resumed run goes on as it began.
RunOptions parse_checkpoint_options(const std::string& yaml_text,
                                    const std::vector<std::string>& overrides,
                                    const std::string& source);

// Every key with its resolved value, as nested YAML (run.yaml, checkpoints).
std::string to_yaml(const RunOptions& o);
// Every key with its resolved value, flat, for summary.json.
std::vector<std::pair<std::string, std::string>> flat_values(const RunOptions& o);
// The table of keys as Markdown, for `capsim params` and the docs.
std::string parameter_table_markdown();

} // namespace capsim
