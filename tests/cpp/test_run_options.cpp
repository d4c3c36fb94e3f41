#include "config/run_options.hpp"
#include "run/automatic_settings.hpp"

#include <algorithm>
#include <catch2/catch.hpp>

using namespace capsim;

namespace {
std::string error_of(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  try {
    parse_run_options(yaml, sets);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
} // namespace

TEST_CASE("config: defaults and nested keys", "[config]") {
  RunOptions o =
      parse_run_options("ca: 0.3\nquadrature:\n  far_ratio: 6\ndt: auto\n", {});
  CHECK(o.ca == 0.3);
  CHECK(o.quadrature.far_ratio == 6);
  CHECK(o.dt == 0);
  CHECK(o.mesh_level == 3);
  o = parse_run_options("ca: 0.3\n", {"ca=0.5", "dt=0.01", "membrane.load=consistent"});
  CHECK(o.ca == 0.5);
  CHECK(o.dt == 0.01);
  CHECK(o.load == LoadMapping::consistent);
  CHECK(o.bending == 0); // the paper's membrane has no bending stiffness
  CHECK(parse_run_options("membrane:\n  bending: 0.05\n", {}).bending == 0.05);
  CHECK_FALSE(o.wrinkling); // the paper's membrane: eq. 2.11, compression included
  CHECK(parse_run_options("membrane:\n  wrinkling: true\n", {}).wrinkling);
  CHECK_FALSE(parse_run_options("", {"membrane.wrinkling=false"}).wrinkling);
  // Written back as a boolean, so run.yaml and the checkpoint keep it.
  const RunOptions w = parse_run_options("", {"membrane.wrinkling=true"});
  CHECK_THAT(to_yaml(w),
             Catch::Contains("membrane:\n") && Catch::Contains("  wrinkling: true\n"));
  CHECK(parse_run_options(to_yaml(w), {}).wrinkling);
  CHECK_THAT(parameter_table_markdown(),
             Catch::Contains("| `membrane.wrinkling` | false | one of {true, false} |"));
}

TEST_CASE("config: bad values name the key and the allowed range", "[config]") {
  CHECK_THAT(error_of("ca: -0.1\n"), Catch::Contains("ca: must be a number in (0, 10]") &&
                                         Catch::Contains("-0.1"));
  CHECK_THAT(error_of("mesh_level: 9\n"),
             Catch::Contains("mesh_level: must be an integer in [1, 5]"));
  CHECK_THAT(error_of("mesh_level: 2.5\n"), Catch::Contains("mesh_level"));
  CHECK_THAT(error_of("ca: fast\n"),
             Catch::Contains("ca: must be a number") && Catch::Contains("'fast'"));
  CHECK_THAT(error_of("viscosity: 2\n"),
             Catch::Contains("unknown key 'viscosity'") && Catch::Contains("known keys"));
  CHECK_THAT(error_of("dt: soon\n"), Catch::Contains("dt: must be 'auto' or a number"));
  CHECK_THAT(error_of("flow: pipe\n"),
             Catch::Contains("flow: must be one of {shear, quiescent}"));
  CHECK_THAT(error_of("t_end: 5\nt_avg_start: 6\n"), Catch::Contains("t_avg_start"));
  CHECK_THAT(error_of("capsules: 3\n"),
             Catch::Contains("capsules: must be 1 when phi = 0"));
  CHECK_THAT(error_of("phi: 0.5\n"),
             Catch::Contains("phi: must be a number in [0, 0.45]"));
  CHECK_THAT(error_of("ewald:\n  xi: -1\n"), Catch::Contains("ewald.xi: must be 'auto'"));
  CHECK_THAT(error_of("membrane:\n  bending: 2\n"),
             Catch::Contains("membrane.bending: must be a number in [0, 1]"));
  CHECK_THAT(
      error_of("membrane:\n  wrinkling: 1\n"),
      Catch::Contains("membrane.wrinkling: must be one of {true, false}, got '1'"));
  CHECK_THAT(error_of("", {"membrane.wrinkling=True"}),
             Catch::Contains("membrane.wrinkling: must be one of {true, false}"));
  CHECK_THAT(error_of("ca: [1, 2]\n"), Catch::Contains("ca: must be a single value"));
  CHECK_THAT(error_of("ca: 0.2\n  bad indent: [\n"), Catch::Contains("not valid YAML"));
  CHECK_THAT(error_of("", {"ca"}), Catch::Contains("must be key=value"));
}

// Found by the fuzzed run files (tests/python/test_fuzz_inputs.py): each of these was
// accepted silently or printed a message over several lines or thousands of characters.
TEST_CASE("config: duplicated keys, empty maps and odd text give one short line",
          "[config]") {
  CHECK_THAT(error_of("ca: 0.3\nca: 0.4\n"), Catch::Contains("ca: given twice"));
  CHECK_THAT(error_of("quadrature:\n  far_ratio: 3\nquadrature.far_ratio: 4\n"),
             Catch::Contains("quadrature.far_ratio: given twice"));
  CHECK(parse_run_options("ca: 0.3\n", {"ca=0.4", "ca=0.5"}).ca == 0.5); // --set: last
  CHECK_THAT(error_of("ca: {}\n"), Catch::Contains("ca: must be a single value"));
  const std::string multi = error_of("ca: |\n  0.3\n  0.4\n");
  CHECK_THAT(multi, Catch::Contains("got '0.3\\x0a0.4\\x0a'"));
  CHECK(multi.find('\n') == std::string::npos);
  const std::string huge = error_of("", {"ca=" + std::string(5000, '9')});
  CHECK_THAT(huge, Catch::Contains("(5000 characters)"));
  CHECK(huge.size() < 200);
  CHECK_THAT(error_of("", {"k\x07=1"}), Catch::Contains("unknown key 'k\\x07'"));
  CHECK(number_problem("nan", false) != "");
  CHECK(number_problem("", true) != "");
  CHECK(number_problem("3", true) == "");
  CHECK_THAT(number_problem("99999999999", true), Catch::Contains("2147483647"));
}

TEST_CASE("config: a checkpoint without a key added later resumes with the value runs "
          "took before it, not today's default",
          "[config]") {
  // Written by a build before the precisions were options: its runs were double.
  const RunOptions old =
      parse_checkpoint_options("ca: 0.2\nphi: 0.3\n", {"t_end=30"}, "c");
  CHECK(old.ewald.precision == Precision::double_precision);
  CHECK(old.ewald.real_space_precision == Precision::double_precision);
  CHECK(old.gmres_guess == GmresGuess::previous);
  CHECK(old.t_end == 30);
  CHECK(parse_run_options("ca: 0.2\n", {}).gmres_guess == GmresGuess::extrapolated);
  CHECK(parse_run_options("ca: 0.2\n", {}).ewald.real_space_precision ==
        Precision::automatic); // today's default, for a new run
  // A checkpoint that stores the key keeps its value.
  const RunOptions stored =
      parse_checkpoint_options(to_yaml(parse_run_options("ca: 0.2\n", {})), {}, "c");
  CHECK(stored.ewald.real_space_precision == Precision::automatic);
}

TEST_CASE("config: the resolved YAML reads back to the same options", "[config]") {
  RunOptions o = parse_run_options("", {"ca=0.35", "quadrature.near_ratio=3", "dt=0.002",
                                        "output.snapshot_interval=0", "threads=1"});
  RunOptions back = parse_run_options(to_yaml(o), {});
  CHECK(flat_values(back) == flat_values(o));
  CHECK_THAT(parameter_table_markdown(), Catch::Contains("`quadrature.far_ratio`"));
}

TEST_CASE("config: tolerances left to auto are resolved from the mesh level",
          "[config]") {
  RunOptions o = parse_run_options("ewald:\n  tolerance: auto\n",
                                   {"time.tolerance=auto", "time.scheme=imex"});
  CHECK(o.ewald.tolerance == kAutomatic);
  const auto values = flat_values(o);
  CHECK(std::find(values.begin(), values.end(),
                  std::pair<std::string, std::string>("ewald.tolerance", "auto")) !=
        values.end());
  CHECK_THAT(
      error_of("", {"ewald.tolerance=0"}),
      Catch::Contains("ewald.tolerance: must be 'auto' or a number in [1e-12, 0.01]"));
  for (int level = 1; level <= 5; ++level) {
    RunOptions r = o;
    r.mesh_level = level;
    resolve_automatic_settings(r, true);
    // A finer mesh has a smaller error, so the tolerances tighten with the level.
    CHECK(r.ewald.tolerance == automatic_ewald_tolerance(level));
    CHECK(r.time.tolerance == automatic_time_tolerance(level));
    if (level > 1) {
      CHECK(automatic_ewald_tolerance(level) <= automatic_ewald_tolerance(level - 1));
      CHECK(automatic_time_tolerance(level) < automatic_time_tolerance(level - 1));
    }
  }
  // The rms norm's time error is larger at equal tolerance (docs/method.md), so its
  // automatic tolerance is the tighter one at every level.
  RunOptions rms = parse_run_options(
      "", {"time.scheme=imex", "time.tolerance=auto", "time.error_norm=rms"});
  resolve_automatic_settings(rms, true);
  CHECK(rms.time.tolerance == automatic_time_tolerance(3, ErrorNorm::rms));
  for (int level = 1; level <= 5; ++level)
    CHECK(automatic_time_tolerance(level, ErrorNorm::rms) <
          automatic_time_tolerance(level, ErrorNorm::max));
  RunOptions heun = parse_run_options("", {"time.tolerance=auto"});
  resolve_automatic_settings(heun, true);
  CHECK(heun.time.tolerance == 0); // Heun keeps its fixed step
}
