#include "config/run_options.hpp"

#include "common/choice.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <yaml-cpp/yaml.h>

namespace capsim {
namespace {

using Range = NumberRange;

std::string format_number(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// One config key: how to read it into RunOptions, how to print it back, what it means.
struct Param {
  std::string key, allowed, help;
  std::function<void(RunOptions&, const std::string&)> set;
  std::function<std::string(const RunOptions&)> get;
};

[[noreturn]] void bad_value(const std::string& key, const std::string& allowed,
                            const std::string& value) {
  throw ConfigError(key + ": must be " + allowed + ", got " + quoted_for_message(value));
}

double parse_double(const std::string& s, bool& ok) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (...) {
    ok = false;
    return 0;
  }
  ok = used == s.size() && std::isfinite(v);
  return v;
}

// The number `s` if it is one within `r`; else the error naming the key.
double number_in(const std::string& key, const std::string& allowed, Range r,
                 const std::string& s) {
  bool ok;
  const double v = parse_double(s, ok);
  if (!ok || !r.contains(v))
    bad_value(key, allowed, s);
  return v;
}

Param real(const std::string& key, Range r, std::function<double&(RunOptions&)> ref,
           const std::string& help) {
  std::string allowed = range_text(r, false);
  return {key, allowed, help,
          [=](RunOptions& o, const std::string& s) {
            ref(o) = number_in(key, allowed, r, s);
          },
          [=](const RunOptions& o) {
            return format_number(ref(const_cast<RunOptions&>(o)));
          }};
}

// 'auto' (stored as `automatic`, a value the range excludes) or a number in `r`.
Param auto_or_real(const std::string& key, Range r, double automatic,
                   std::function<double&(RunOptions&)> ref, const std::string& help) {
  std::string allowed = "'auto' or " + range_text(r, false);
  return {key, allowed, help,
          [=](RunOptions& o, const std::string& s) {
            ref(o) = s == "auto" ? automatic : number_in(key, allowed, r, s);
          },
          [=](const RunOptions& o) {
            const double v = ref(const_cast<RunOptions&>(o));
            return v == automatic ? "auto" : format_number(v);
          }};
}

Param integer(const std::string& key, Range r, std::function<int&(RunOptions&)> ref,
              const std::string& help) {
  std::string allowed = range_text(r, true);
  return {key, allowed, help,
          [=](RunOptions& o, const std::string& s) {
            bool ok;
            double v = parse_double(s, ok);
            if (!ok || v != std::floor(v) || !r.contains(v))
              bad_value(key, allowed, s);
            ref(o) = int(v);
          },
          [=](const RunOptions& o) {
            return std::to_string(ref(const_cast<RunOptions&>(o)));
          }};
}

// true or false, spelled so (as a choice key takes its names: one spelling each).
Param boolean(const std::string& key, std::function<bool&(RunOptions&)> ref,
              const std::string& help) {
  const std::string allowed = "one of {true, false}";
  return {key, allowed, help,
          [=](RunOptions& o, const std::string& s) {
            if (s != "true" && s != "false")
              bad_value(key, allowed, s);
            ref(o) = s == "true";
          },
          [=](const RunOptions& o) -> std::string {
            return ref(const_cast<RunOptions&>(o)) ? "true" : "false";
          }};
}

// "one of {a, b, c}"
std::string one_of(const std::vector<std::string>& names) {
  std::string allowed = "one of {";
  for (size_t i = 0; i < names.size(); ++i)
    allowed += (i ? ", " : "") + names[i];
  return allowed + "}";
}

Param choice(const std::string& key, std::vector<std::string> names,
             std::function<std::string&(RunOptions&)> ref, const std::string& help) {
  const std::string allowed = one_of(names);
  return {key, allowed, help,
          [=](RunOptions& o, const std::string& s) {
            for (const auto& n : names)
              if (n == s)
                return void(ref(o) = s);
            bad_value(key, allowed, s);
          },
          [=](const RunOptions& o) { return ref(const_cast<RunOptions&>(o)); }};
}

// A key that takes one of `names`, stored as an enum: set parses a name already checked
// against `names` (so the message is the same as for every choice key), get names it.
Param named(const std::string& key, std::vector<std::string> names,
            std::function<void(RunOptions&, const std::string&)> set,
            std::function<std::string(const RunOptions&)> get, const std::string& help) {
  const std::string allowed = one_of(names);
  return {key, allowed, help,
          [=](RunOptions& o, const std::string& s) {
            if (std::find(names.begin(), names.end(), s) == names.end())
              bad_value(key, allowed, s);
            set(o, s);
          },
          get};
}

// E comes from the table alone (a lambda is no std::function to deduce it from).
template <class T> struct NotDeduced { using type = T; };

// A key stored as an enum whose names are the table `choices` (the one place they are
// written, next to the enum).
template <class E, std::size_t N>
Param named(const std::string& key, const Choice<E> (&choices)[N],
            typename NotDeduced<std::function<E&(RunOptions&)>>::type ref,
            const std::string& help) {
  std::vector<std::string> names;
  for (const Choice<E>& c : choices)
    names.push_back(c.first);
  return named(
      key, names,
      [key, ref, &choices](RunOptions& o, const std::string& s) {
        ref(o) = parse_choice(key.c_str(), s, choices);
      },
      [ref, &choices](const RunOptions& o) {
        return choice_name(ref(const_cast<RunOptions&>(o)), choices);
      },
      help);
}

const std::vector<Param>& parameters();

} // namespace

bool NumberRange::contains(double v) const {
  return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

// Integers print in full (100000, not 1e+05).
std::string bound_text(double v, bool integer) {
  return integer && std::abs(v) < 1e18 ? std::to_string(static_cast<long long>(v))
                                       : format_number(v);
}

std::string range_text(NumberRange r, bool integer) {
  std::string kind = integer ? "an integer in " : "a number in ";
  return kind + (r.lo_open ? "(" : "[") + bound_text(r.lo, integer) + ", " +
         bound_text(r.hi, integer) + (r.hi_open ? ")" : "]");
}

// Whatever was typed (a line break, an escape sequence, a megabyte of text), the error
// stays one readable line.
std::string quoted_for_message(const std::string& text) {
  constexpr std::size_t kShown = 60;
  std::string out = "'";
  for (std::size_t i = 0; i < std::min(text.size(), kShown); ++i) {
    const auto ch = static_cast<unsigned char>(text[i]);
    if (ch < 0x20 || ch == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", unsigned(ch));
      out += buf;
    } else {
      out += char(ch);
    }
  }
  out += "'";
  if (text.size() > kShown)
    out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

std::string number_problem(const std::string& text, bool integer) {
  bool ok;
  const double v = parse_double(text, ok);
  if (!ok || (integer && v != std::floor(v)))
    return std::string("must be ") + (integer ? "an integer" : "a finite number") +
           ", got " + quoted_for_message(text);
  const Range int_range{double(std::numeric_limits<int>::min()),
                        double(std::numeric_limits<int>::max())};
  if (integer && !int_range.contains(v))
    return "must be " + range_text(int_range, true) + ", got " + quoted_for_message(text);
  return "";
}

void require_in(const std::string& name, double v, NumberRange r, bool integer) {
  if (!r.contains(v))
    throw ConfigError(name + ": must be " + range_text(r, integer) + ", got " +
                      bound_text(v, integer));
}

namespace {

constexpr double kBig = 1e5;

const std::vector<Param>& parameters() {
  static const std::vector<Param> table = {
      real(
          "ca", {0, 10, true, false}, [](RunOptions& o) -> double& { return o.ca; },
          "capillary number Ca = mu gammadot a / Gs"),
      real(
          "phi", {0, 0.45, false, false}, [](RunOptions& o) -> double& { return o.phi; },
          "volume fraction; 0 = one capsule in unbounded shear (dilute limit)"),
      real(
          "lambda", {0.01, 100, false, false},
          [](RunOptions& o) -> double& { return o.lambda; },
          "viscosity ratio of the capsule's interior to the suspending fluid; 1 = equal "
          "(the paper); otherwise, on the CPU backend, the velocity solves the "
          "second-kind boundary integral equation by GMRES (in a suspension with the "
          "periodic double layer, summed as the single layer is)"),
      real(
          "gmres.tolerance", {1e-12, 1e-2, false, false},
          [](RunOptions& o) -> double& { return o.gmres_tolerance; },
          "lambda != 1: GMRES stops when the second-kind equation's residual is this "
          "fraction of its right-hand side; the velocity is then off by about twice "
          "that, far below the discretisation error (5e-3 at mesh_level 3); each decade "
          "tighter costs about two double layers per evaluation"),
      named(
          "gmres.guess", kGmresGuesses,
          [](RunOptions& o) -> GmresGuess& { return o.gmres_guess; },
          "lambda != 1: GMRES's first guess, previous (the latest evaluation's velocity) "
          "or extrapolated (linear in time through the latest velocities at the two "
          "latest evaluation times: off by O(dt^2) instead of O(dt), so fewer "
          "iterations reach gmres.tolerance)"),
      named(
          "method", kEwaldMethods,
          [](RunOptions& o) -> EwaldMethod& { return o.ewald.method; },
          "periodic sums (phi > 0): spectral (Spectral Ewald, FFT), direct (plain "
          "Ewald, the reference) or patches (plain Ewald with the reciprocal sum over "
          "multipole patches, the paper's coarse graining)"),
      integer(
          "capsules", {1, 10000, false, false},
          [](RunOptions& o) -> int& { return o.capsules; },
          "capsules per periodic box (must be 1 when phi = 0)"),
      integer(
          "mesh_level", {1, 5, false, false},
          [](RunOptions& o) -> int& { return o.mesh_level; },
          "icosphere level: 2, 3, 4 = 320, 1280, 5120 triangles per capsule"),
      auto_or_real(
          "dt", {0, 1, true, false}, 0, [](RunOptions& o) -> double& { return o.dt; },
          "time step in strain units; auto = dt_safety * Ca * h / (1 + 4 "
          "membrane.bending "
          "/ h^2), h the mean edge of the mesh"),
      real(
          "dt_safety", {0, 2, true, false},
          [](RunOptions& o) -> double& { return o.dt_safety; },
          "C in the automatic time step dt = C Ca h / (1 + 4 membrane.bending / h^2)"),
      real(
          "dt_lambda_max", {1, 50, false, false},
          [](RunOptions& o) -> double& { return o.dt_lambda_max; },
          "lambda > 1: the automatic step grows as (1 + lambda)/2 times lambda 1's "
          "(Heun's limit, the relaxation of the mesh-scale membrane waves, moves so) up "
          "to this factor; 1 keeps lambda 1's step. The time error of the capsules' "
          "slow motion grows as dt^2: 2 and 3 save 1.5 and 2.1 times at lambda 5, "
          "Ca 0.2, within a tenth and a quarter of the level-3 mesh error of D there "
          "(docs/time_stepping.md)"),
      named(
          "time.scheme", kTimeSchemes,
          [](RunOptions& o) -> TimeScheme& { return o.time.scheme; },
          "heun (explicit 2nd-order Runge-Kutta, eq. 3.2: stable for dt ~ Ca h), imex "
          "(linearly implicit 2nd-order Rosenbrock-W: each capsule's own membrane "
          "stiffness implicit, the rest explicit; steps far beyond Ca h) or rkc "
          "(explicit 2nd-order Runge-Kutta-Chebyshev of time.stages stages: steps "
          "beta(s) / 2 times Heun's for s / 2 times the work, beta(4) / 2 = 4.9)"),
      integer(
          "time.stages", {2, 20, false, false},
          [](RunOptions& o) -> int& { return o.time.stages; },
          "time.scheme rkc: its stages s; the automatic step is beta(s) / 2 times "
          "Heun's (beta(s) ~ 0.65 s^2, its stability boundary), so dt_safety keeps "
          "its margin to the stability limit"),
      auto_or_real(
          "time.tolerance", {0, 1, false, false}, kAutomatic,
          [](RunOptions& o) -> double& { return o.time.tolerance; },
          "adaptive step: the largest position error one step may make (time.error_norm "
          "of the node errors), in capsule radii (embedded estimate); dt is then only "
          "the first step. 0 = a fixed step dt; auto = 0 for heun, for imex the "
          "tolerance whose time error stays below a tenth of the mesh error at "
          "mesh_level with the chosen time.error_norm (docs/method.md)"),
      named(
          "time.error_norm", kErrorNorms,
          [](RunOptions& o) -> ErrorNorm& { return o.time.error_norm; },
          "how the adaptive step measures a step's node errors: max (the largest over "
          "all nodes) or rms (the root mean square over each capsule's nodes, the "
          "largest over capsules)"),
      real(
          "t_end", {0, kBig, true, false},
          [](RunOptions& o) -> double& { return o.t_end; },
          "end of the run, in strain units gammadot t"),
      real(
          "t_avg_start", {0, kBig, false, false},
          [](RunOptions& o) -> double& { return o.t_avg_start; },
          "start of the time-averaging window (must be < t_end)"),
      integer(
          "seed", {0, 2147483647.0, false, false},
          [](RunOptions& o) -> int& { return o.seed; },
          "random seed for initial positions"),
      choice(
          "flow", {"shear", "quiescent"},
          [](RunOptions& o) -> std::string& { return o.flow; },
          "undisturbed flow: simple shear v = (y, 0, 0), or quiescent fluid"),
      real(
          "initial.stretch", {0.5, 2, false, false},
          [](RunOptions& o) -> double& { return o.initial_stretch; },
          "initial shape x -> (s x, y/sqrt s, z/sqrt s) of the reference sphere"),
      named(
          "membrane.load", kLoadMappings,
          [](RunOptions& o) -> LoadMapping& { return o.load; },
          "nodal forces -> traction q: lumped (q = F/A_node) or consistent (M q = F; "
          "needs dt_safety <= 0.2)"),
      named(
          "membrane.law", kMembraneLaws,
          [](RunOptions& o) -> MembraneLaw& { return o.law; },
          "the interface: neo_hookean (the paper's membrane, eq. 2.11) or drop (an "
          "isotropic surface tension sigma, Ca = mu gammadot a / sigma; its nodes move "
          "with the interface's normal velocity, and heun or rkc steps)"),
      real(
          "membrane.bending", {0, 1, false, false},
          [](RunOptions& o) -> double& { return o.bending; },
          "bending modulus kb / (Gs a^2) of a hinge energy that damps element-scale "
          "folds; 0 = none (the paper's membrane)"),
      boolean(
          "membrane.wrinkling", [](RunOptions& o) -> bool& { return o.wrinkling; },
          "the relaxed (tension-field) neo-Hookean energy: equal to eq. 2.11 where both "
          "principal tensions are >= 0, no compressive tension (a wrinkled element is "
          "taut along its stretched direction only), none in a slack element; false = "
          "eq. 2.11 (the paper's membrane)"),
      real(
          "quadrature.far_ratio", {1, 50, false, false},
          [](RunOptions& o) -> double& { return o.quadrature.far_ratio; },
          "triangles closer than this many diameters get accurate quadrature"),
      real(
          "quadrature.near_ratio", {0.5, 20, false, false},
          [](RunOptions& o) -> double& { return o.quadrature.near_ratio; },
          "near-singular subdivision until pieces are this many diameters away"),
      integer(
          "quadrature.max_depth", {0, 12, false, false},
          [](RunOptions& o) -> int& { return o.quadrature.max_depth; },
          "deepest 1-to-4 subdivision of a near-singular triangle"),
      integer(
          "quadrature.singular_points", {2, 64, false, false},
          [](RunOptions& o) -> int& { return o.quadrature.singular_points; },
          "Gauss-Legendre points of the polar rule at a vertex"),
      auto_or_real(
          "ewald.tolerance", {1e-12, 1e-2, false, false}, kAutomatic,
          [](RunOptions& o) -> double& { return o.ewald.tolerance; },
          "truncation tolerance of the Ewald sums (phi > 0); auto = the tolerance whose "
          "error stays below a tenth of the mesh error at mesh_level (docs/method.md)"),
      auto_or_real(
          "ewald.xi", {0, 100, true, false}, 0,
          [](RunOptions& o) -> double& { return o.ewald.xi; },
          "Ewald splitting parameter; auto: for spectral the xi of least modelled cost "
          "(real-space pairs against grid FFTs), for direct the cost balance of the two "
          "sums, for patches their balance at equal cost per term (which holds the "
          "coarse-graining error)"),
      integer(
          "ewald.patch_level", {0, 3, false, false},
          [](RunOptions& o) -> int& { return o.ewald.patch_level; },
          "method patches: the patches are the faces of this icosphere level (0, 1, 2, "
          "3: P = 20, 80, 320, 1280 per capsule); at most mesh_level"),
      named(
          "ewald.precision", {"double", "single", "auto"},
          [](RunOptions& o, const std::string& s) {
            o.ewald.precision = parse_precision(s);
          },
          [](const RunOptions& o) { return to_string(o.ewald.precision); },
          "method spectral: the precision of its grids and FFTs; auto = single where "
          "ewald.tolerance >= 1e-5 (its rounding, about 3e-7 of the velocities, is then "
          "at most a thirtieth of the tolerance) and the backend has single grids (cpu), "
          "double otherwise"),
      named(
          "ewald.real_space_precision", {"double", "single", "auto"},
          [](RunOptions& o, const std::string& s) {
            o.ewald.real_space_precision = parse_precision(s);
          },
          [](const RunOptions& o) { return to_string(o.ewald.real_space_precision); },
          "the precision of the real-space sum's separations and kernel (the sums per "
          "target in double); auto = single where ewald.tolerance >= 1e-5 (its rounding, "
          "about 1e-7 of the velocities, is then at most a hundredth of the tolerance) "
          "and the backend has it (cpu), double otherwise"),
      real(
          "suspension.min_gap", {0, 2, false, false},
          [](RunOptions& o) -> double& { return o.suspension.min_gap; },
          "smallest surface gap between capsules in the initial packing (phi > 0)"),
      real(
          "suspension.stop_distance", {0, 1, false, false},
          [](RunOptions& o) -> double& { return o.suspension.stop_distance; },
          "stop the run when nodes of two capsules come this close (phi > 0)"),
      real(
          "suspension.repulsion_force", {0, 100, false, false},
          [](RunOptions& o) -> double& { return o.suspension.repulsion.force; },
          "short-range repulsion between nodes of different capsules: force at contact, "
          "in mu gammadot a^2 (the scale of the flow that presses capsules together); "
          "0 = off (the paper has none)"),
      real(
          "suspension.repulsion_range", {0, 1, true, false},
          [](RunOptions& o) -> double& { return o.suspension.repulsion.range; },
          "distance below which the repulsion acts, in a"),
      real(
          "output.sample_interval", {0, kBig, true, false},
          [](RunOptions& o) -> double& { return o.output.sample_interval; },
          "strain between rows of timeseries.h5"),
      real(
          "output.checkpoint_interval", {0, kBig, true, false},
          [](RunOptions& o) -> double& { return o.output.checkpoint_interval; },
          "strain between checkpoints"),
      real(
          "output.snapshot_interval", {0, kBig, false, false},
          [](RunOptions& o) -> double& { return o.output.snapshot_interval; },
          "strain between mesh snapshots (XDMF); 0 = none"),
      integer(
          "threads", {0, 1024, false, false},
          [](RunOptions& o) -> int& { return o.threads; },
          "OpenMP threads; 0 = the OpenMP default"),
      named(
          "backend", kBackends, [](RunOptions& o) -> Backend& { return o.backend; },
          "where the flow is evaluated: cpu (OpenMP) or cuda (one GPU; lumped load, "
          "the spectral method)"),
  };
  return table;
}

const Param& find_param(const std::string& key) {
  for (const auto& p : parameters())
    if (p.key == key)
      return p;
  std::string known;
  for (const auto& p : parameters())
    known += (known.empty() ? "" : ", ") + p.key;
  throw ConfigError("unknown key " + quoted_for_message(key) + " (known keys: " + known +
                    ")");
}

// A key as the messages name it: plainly, unless it holds more than letters, digits,
// '_' and '.' (then quoted and escaped by quoted_for_message).
std::string key_for_message(const std::string& key) {
  for (const char ch : key)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '.')
      return quoted_for_message(key);
  return key.empty() ? "''" : key;
}

// A key given twice (`ca` twice, or `quadrature: {far_ratio: ..}` and
// `quadrature.far_ratio`) is refused: YAML forbids it, and which value would count is
// not obvious to the reader of the file.
void flatten(const YAML::Node& node, const std::string& prefix,
             std::vector<std::pair<std::string, std::string>>& out) {
  for (const auto& kv : node) {
    std::string key = prefix + kv.first.as<std::string>();
    if (kv.second.IsMap() && kv.second.size() > 0) {
      flatten(kv.second, key + ".", out);
      continue;
    }
    if (!kv.second.IsScalar())
      throw ConfigError(key_for_message(key) +
                        ": must be a single value, not a list, a map or an empty entry");
    for (const auto& [seen, value] : out)
      if (seen == key)
        throw ConfigError(key_for_message(key) + ": given twice");
    out.emplace_back(key, kv.second.as<std::string>());
  }
}

// Checks that involve more than one key.
void validate(const RunOptions& o) {
  if (o.t_avg_start >= o.t_end)
    throw ConfigError("t_avg_start: must be smaller than t_end (" +
                      format_number(o.t_end) + "), got " + format_number(o.t_avg_start));
  if (o.phi == 0 && o.capsules != 1)
    throw ConfigError("capsules: must be 1 when phi = 0 (the dilute limit), got " +
                      std::to_string(o.capsules));
  if (o.law == MembraneLaw::drop) {
    if (o.bending != 0)
      throw ConfigError("membrane.bending: must be 0 with membrane.law: drop, got " +
                        format_number(o.bending));
    if (o.wrinkling)
      throw ConfigError("membrane.wrinkling: must be false with membrane.law: drop");
    if (o.time.scheme == TimeScheme::imex)
      throw ConfigError("time.scheme: must be heun or rkc with membrane.law: drop (imex "
                        "needs the membrane's Jacobian, which a drop has not), got imex");
  }
  if (o.ewald.method == EwaldMethod::patches && o.ewald.patch_level > o.mesh_level)
    throw ConfigError("ewald.patch_level: must be at most mesh_level (" +
                      std::to_string(o.mesh_level) + ") with method: patches, got " +
                      std::to_string(o.ewald.patch_level));
}

} // namespace

namespace {

// The (key, value) entries of YAML text, nested maps flattened to dotted keys.
std::vector<std::pair<std::string, std::string>>
yaml_entries(const std::string& yaml_text, const std::string& source) {
  std::vector<std::pair<std::string, std::string>> entries;
  try {
    YAML::Node root = YAML::Load(yaml_text);
    if (root && !root.IsNull()) {
      if (!root.IsMap())
        throw ConfigError(source + ": must be a map of key: value entries");
      flatten(root, "", entries);
    }
  } catch (const YAML::Exception& e) {
    throw ConfigError(source + ": not valid YAML: " + e.what());
  }
  return entries;
}

} // namespace

RunOptions parse_run_options(const std::string& yaml_text,
                             const std::vector<std::string>& overrides,
                             const std::string& source) {
  std::vector<std::pair<std::string, std::string>> entries =
      yaml_entries(yaml_text, source);
  for (const auto& s : overrides) {
    auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw ConfigError("--set " + quoted_for_message(s) + ": must be key=value");
    entries.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  RunOptions o;
  for (const auto& [key, value] : entries)
    find_param(key).set(o, value);
  validate(o);
  return o;
}

namespace {

// The keys added after runs were first checkpointed whose value then differs from today's
// default, with the value those runs took (pipeline/run_spec.py ADDED_OPTIONS keys the
// archive's records by the same values). The other added keys (lambda, membrane.law,
// time.stages, gmres.tolerance) default to what runs took before them.
const std::vector<std::pair<std::string, std::string>> kFormerValues = {
    {"ewald.precision", "double"},
    {"ewald.real_space_precision", "double"},
    {"gmres.guess", "previous"},
};

} // namespace

RunOptions parse_checkpoint_options(const std::string& yaml_text,
                                    const std::vector<std::string>& overrides,
                                    const std::string& source) {
  const auto stored = yaml_entries(yaml_text, source);
  std::vector<std::string> sets;
  for (const auto& [key, value] : kFormerValues) {
    const bool present = std::any_of(stored.begin(), stored.end(),
                                     [&](const auto& kv) { return kv.first == key; });
    if (!present)
      sets.push_back(key + "=" + value);
  }
  sets.insert(sets.end(), overrides.begin(), overrides.end());
  return parse_run_options(yaml_text, sets, source);
}

RunOptions load_run_options(const std::string& yaml_path,
                            const std::vector<std::string>& overrides) {
  std::string text;
  if (!yaml_path.empty()) {
    std::ifstream in(yaml_path);
    if (!in)
      throw ConfigError("cannot read run file '" + yaml_path + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  return parse_run_options(text, overrides, yaml_path.empty() ? "defaults" : yaml_path);
}

std::vector<std::pair<std::string, std::string>> flat_values(const RunOptions& o) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& p : parameters())
    out.emplace_back(p.key, p.get(o));
  return out;
}

std::string to_yaml(const RunOptions& o) {
  // Keys are grouped by their prefix (quadrature.*, output.*, ...), in table order.
  std::ostringstream s;
  std::string group;
  for (const auto& [key, value] : flat_values(o)) {
    auto dot = key.find('.');
    std::string g = dot == std::string::npos ? "" : key.substr(0, dot);
    if (g != group && !g.empty())
      s << g << ":\n";
    group = g;
    s << (g.empty() ? "" : "  ") << key.substr(dot == std::string::npos ? 0 : dot + 1)
      << ": " << value << "\n";
  }
  return s.str();
}

std::string parameter_table_markdown() {
  RunOptions defaults;
  std::ostringstream s;
  s << "| key | default | allowed | meaning |\n|---|---|---|---|\n";
  for (const auto& p : parameters())
    s << "| `" << p.key << "` | " << p.get(defaults) << " | " << p.allowed << " | "
      << p.help << " |\n";
  return s.str();
}

} // namespace capsim
