// capsim: the command-line front end. Parses arguments and hands over to the run loop;
// every error reaches the user as one readable line and a non-zero exit code.
#include "config/run_options.hpp"
#include "dynamics/flow.hpp"
#include "dynamics/simulation_error.hpp"
#include "io/json_writer.hpp"
#include "run/automatic_settings.hpp"
#include "run/backend_selftest.hpp"
#include "run/bench.hpp"
#include "run/multipole_error.hpp"
#include "run/simulation.hpp"
#include "stokes/kernels/periodic_stokeslet.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <malloc.h>
#include <omp.h>

namespace {

constexpr int kExitConfig = 2;    // bad input: nothing was changed
constexpr int kExitNumerical = 3; // numerical failure: the last checkpoint stays
constexpr int kExitIo = 4;        // files could not be read or written

// CLI11 checks of number options with the rules of the run keys (capsim::number_problem):
// empty text, NaN, infinities, words and, for integers, fractions are refused with the
// option named; the ranges are checked where the options are used.
CLI::Validator finite_number() {
  return {[](std::string& s) { return capsim::number_problem(s, false); }, "NUMBER"};
}
CLI::Validator whole_number() {
  return {[](std::string& s) { return capsim::number_problem(s, true); }, "INT"};
}

struct RunArgs {
  std::string runfile, outdir, resume_dir, branch_dir;
  std::vector<std::string> sets;
  bool quiet = false;
  double pause_at = 0;
  std::string profile;
};

void add_run_command(CLI::App& app, RunArgs& a) {
  CLI::App* run = app.add_subcommand(
      "run",
      "Simulate capsules in shear flow and write timeseries.h5, snapshots, checkpoints "
      "and summary.json into the output folder");
  run->add_option("RUNFILE", a.runfile, "run file (YAML); keys: see `capsim params`")
      ->check(CLI::ExistingFile);
  run->add_option("--set", a.sets,
                  "override a key: --set ca=0.3 --set quadrature.far_ratio=6")
      ->type_name("KEY=VALUE");
  run->add_option("-o,--output", a.outdir, "output folder for a new run");
  run->add_option(
      "--resume", a.resume_dir,
      "continue the run in this folder from its last checkpoint (with --set, only "
      "t_end, t_avg_start, threads, backend and output.* may change)");
  run->add_option("--branch", a.branch_dir,
                  "start a new run (-o) from the last checkpoint of the run in this "
                  "folder, with its time series up to there; with --set, the keys of "
                  "--resume and the numerics (method, dt, dt_safety, dt_lambda_max, "
                  "time.*, ewald.*, quadrature.*, gmres.*) may change, e.g. to compare "
                  "time schemes or steps from a developed suspension (another fixed "
                  "step counts its steps from the checkpoint's time)")
      ->check(CLI::ExistingDirectory);
  run->add_flag("-q,--quiet", a.quiet, "no progress lines on stderr");
  run->add_option("--pause-at", a.pause_at,
                  "run one segment: stop at the first checkpoint at or after this "
                  "gammadot t, without summary.json (exit 0); --resume continues the "
                  "run to the last bit as if it had not stopped")
      ->check(finite_number())
      ->type_name("T");
  run->add_option("--profile", a.profile,
                  "write the wall seconds of every stage of the steps (membrane load, "
                  "near corrections, real space, spreading, FFT, gathering, volume "
                  "constraint, sampling, checkpoints, ...) to this JSON file")
      ->type_name("FILE");
}

struct ParamsArgs {
  bool json = false;
  std::vector<std::string> sets;
};

CLI::App* add_params_command(CLI::App& app, ParamsArgs& a) {
  CLI::App* params = app.add_subcommand(
      "params", "List every run-file key with its default and allowed range (Markdown)");
  params->add_flag("--json", a.json,
                   "print instead every key with the value a run takes, as JSON: the "
                   "defaults with the --set keys applied and the automatic tolerances "
                   "resolved, as run.yaml would hold them");
  params->add_option("--set", a.sets, "with --json: a key as `capsim run --set` takes it")
      ->type_name("KEY=VALUE");
  return params;
}

// The workflow's results archive compares a run's options with what this prints, so
// that a default changed in the solver's table is seen (pipeline/run_spec.py).
int params_command(const ParamsArgs& a) {
  if (!a.json) {
    if (!a.sets.empty())
      throw capsim::ConfigError("params: --set needs --json");
    std::cout << capsim::parameter_table_markdown();
    return 0;
  }
  capsim::RunOptions o = capsim::parse_run_options("", a.sets, "--set");
  capsim::resolve_automatic_settings(o, true);
  capsim::JsonWriter json;
  json.begin_object();
  for (const auto& [key, value] : capsim::flat_values(o))
    json.field(key, value);
  json.end_object();
  std::cout << json.str();
  return 0;
}

struct GreensArgs {
  double box = 0, strain = 0, xi = 0, tolerance = 1e-12;
  std::vector<double> point;
};

void add_greens_command(CLI::App& app, GreensArgs& a) {
  CLI::App* g = app.add_subcommand(
      "greens",
      "Print the periodic Stokeslet J^E (paper eq. 2.3) of a sheared cubic lattice "
      "at one point, as JSON, to check the kernel");
  g->add_option("--box", a.box, "box side L (capsule radii), in [1e-6, 1e6]")
      ->required()
      ->check(finite_number());
  g->add_option("--strain", a.strain,
                "lattice strain offset s (wrapped into [-1/2, 1/2)), in [-1e6, 1e6]")
      ->check(finite_number());
  g->add_option("--xi", a.xi,
                "Ewald splitting parameter (default sqrt(pi)/L); xi L in [0.1, 30]")
      ->check(finite_number());
  g->add_option("--tolerance", a.tolerance,
                "truncation tolerance of both sums, in [1e-16, 0.1]")
      ->check(finite_number());
  g->add_option("--point", a.point,
                "field point x y z relative to the source, each in [-1e6, 1e6]")
      ->required()
      ->expected(3)
      ->check(finite_number());
}

// Outside these ranges the sums either lose their accuracy or their cost explodes: the
// real-space sum visits (r_cut / L)^3 ~ (xi L)^-3 images and the reciprocal sum
// (k_cut L)^3 ~ (xi L)^3 wave vectors, so xi L is bounded on both sides (at the bounds
// one evaluation takes well under a second).
void check_greens(const GreensArgs& a) {
  capsim::require_in("--box", a.box, {1e-6, 1e6});
  capsim::require_in("--strain", a.strain, {-1e6, 1e6});
  capsim::require_in("--tolerance", a.tolerance, {1e-16, 0.1});
  for (double x : a.point)
    capsim::require_in("--point", x, {-1e6, 1e6});
  if (a.xi != 0)
    capsim::require_in("--xi (xi L must be in [0.1, 30])", a.xi,
                       {0.1 / a.box, 30 / a.box});
}

int greens_command(const GreensArgs& a) {
  check_greens(a);
  capsim::ShearedLattice lattice = capsim::make_sheared_lattice(a.box, a.strain);
  capsim::EwaldParameters p = capsim::choose_ewald_parameters(a.box, a.tolerance, a.xi);
  capsim::EwaldCounts counts;
  capsim::Vec3 r{a.point[0], a.point[1], a.point[2]};
  capsim::Mat3 j;
  try {
    j = capsim::periodic_stokeslet(lattice, r, p, &counts);
  } catch (const std::invalid_argument& e) {
    throw capsim::ConfigError(std::string("--point: ") + e.what());
  }
  capsim::JsonWriter w;
  w.begin_object();
  w.matrix("J", j);
  w.field("normalisation", "v(x) = -1/(8 pi mu) J^E(x - y) q: J^E = I/r + r r/r^3 + ...");
  w.field("box", a.box);
  w.field("strain", lattice.s);
  w.field("xi", p.xi);
  w.field("r_cut", p.r_cut);
  w.field("k_cut", p.k_cut);
  w.field("images", counts.images);
  w.field("wave_vectors", counts.wave_vectors);
  w.end_object();
  std::cout << w.str();
  return 0;
}

struct MultipoleArgs {
  std::string run_dir, output;
  std::vector<int> patches = {1, 20, 80, 320, 1280};
  std::vector<double> distances = {2, 2.5, 3, 4, 5, 6, 8, 10, 12, 15, 20};
};

void add_multipole_command(CLI::App& app, MultipoleArgs& a) {
  CLI::App* m = app.add_subcommand(
      "multipole-error",
      "Error of the multipole-patch coarse graining around the capsule of a run's "
      "checkpoint, against fine quadrature (paper eq. 3.11, figure 1), as CSV");
  m->add_option("RUNDIR", a.run_dir,
                "a run folder with checkpoint.h5 (e.g. a dilute run)")
      ->required()
      ->check(CLI::ExistingDirectory);
  m->add_option("--patches", a.patches, "patch counts P (1 or 20 * 4^l)");
  m->add_option("--distances", a.distances, "distances r/a from the centroid")
      ->check(CLI::Range(1.0, 1e4));
  m->add_option("-o,--output", a.output, "CSV file (default: standard output)");
}

int multipole_command(const MultipoleArgs& a) {
  std::string csv = capsim::multipole_error_csv(
      capsim::multipole_error(a.run_dir, a.patches, a.distances));
  if (a.output.empty())
    std::cout << csv;
  else
    capsim::write_text_atomically(a.output, csv);
  return 0;
}

// A CLI11 check of an option that takes one of the names of `choices`, with the message
// of the run keys ("--method: must be one of {spectral, direct, patches}, got 'ewald'").
template <class E, std::size_t N>
CLI::Validator one_of(const capsim::Choice<E> (&choices)[N]) {
  return {[&choices](std::string& s) {
            for (const capsim::Choice<E>& c : choices)
              if (s == c.first)
                return std::string();
            return "must be one of {" + capsim::choice_list(choices) + "}, got " +
                   capsim::quoted_for_message(s);
          },
          ""};
}

// --precision and --real-space-precision: a precision as ewald.precision takes it.
void add_precision_option(CLI::App* b, const std::string& name, capsim::Precision& into,
                          const std::string& help) {
  b->add_option_function<std::string>(
       name, [&into](const std::string& s) { into = capsim::parse_precision(s); }, help)
      ->default_str(capsim::to_string(into))
      ->check(CLI::IsMember({"double", "single", "auto"}));
}

struct BenchArgs {
  capsim::BenchOptions o;
  int threads = 0;
};

void add_bench_command(CLI::App& app, BenchArgs& a) {
  CLI::App* b = app.add_subcommand(
      "bench", "Time one periodic single-layer evaluation of M capsules and measure its "
               "error against a tight direct Ewald reference; prints JSON");
  b->add_option("--capsules", a.o.capsules, "capsules M in the box")
      ->capture_default_str()
      ->check(whole_number());
  b->add_option("--mesh-level", a.o.mesh_level, "icosphere level")
      ->capture_default_str()
      ->check(whole_number());
  b->add_option("--phi", a.o.phi, "volume fraction")
      ->capture_default_str()
      ->check(finite_number());
  b->add_option_function<std::string>(
       "--method",
       [&a](const std::string& s) { a.o.ewald.method = capsim::parse_ewald_method(s); },
       "spectral | direct | patches")
      ->default_str("spectral")
      ->check(one_of(capsim::kEwaldMethods));
  b->add_option("--patch-level", a.o.ewald.patch_level,
                "method patches: icosphere level of the patches (1: P = 80)")
      ->capture_default_str()
      ->check(whole_number());
  add_precision_option(b, "--precision", a.o.ewald.precision,
                       "method spectral: its grids and FFTs in double, single or auto "
                       "precision (as ewald.precision, whose default in a run is auto)");
  add_precision_option(b, "--real-space-precision", a.o.ewald.real_space_precision,
                       "the real-space sum in double, single or auto precision (as "
                       "ewald.real_space_precision, whose default in a run is auto)");
  b->add_option("--tolerance", a.o.ewald.tolerance, "Ewald tolerance")
      ->capture_default_str()
      ->check(finite_number());
  b->add_option("--strain", a.o.strain, "lattice strain offset")
      ->capture_default_str()
      ->check(finite_number());
  b->add_option("--seed", a.o.seed, "packing seed")
      ->capture_default_str()
      ->check(whole_number());
  b->add_option("--xi", a.o.ewald.xi, "Ewald xi (default: automatic, as in `capsim run`)")
      ->check(finite_number());
  b->add_option("--repeats", a.o.repeats, "timed evaluations")
      ->capture_default_str()
      ->check(whole_number());
  b->add_option("--reference", a.o.reference_file,
                "file caching the reference velocities of this configuration");
  b->add_flag(
      "--no-reference", [&a](int64_t) { a.o.reference = false; },
      "skip the reference and the error");
  b->add_option("--threads", a.threads, "OpenMP threads (default: all)")
      ->check(whole_number());
}

int bench_command(const BenchArgs& a) {
  capsim::require_in("--threads", a.threads, {0, 1024}, true); // as the run key
  if (a.threads > 0)
    omp_set_num_threads(a.threads);
  std::cout << capsim::run_benchmark(a.o) << "\n";
  return 0;
}

void add_selftest_command(CLI::App& app, std::string& backend) {
  CLI::App* s = app.add_subcommand(
      "selftest",
      "Compare a backend with the CPU backend on a few evaluations and short "
      "runs, and print the differences (for checking the CUDA backend on a GPU)");
  s->add_option("--backend", backend, "backend to check: cpu or cuda")
      ->check(CLI::IsMember({"cpu", "cuda"}));
}

int run_command(const RunArgs& a) {
  capsim::RunRequest request;
  request.quiet = a.quiet;
  if (!a.resume_dir.empty()) {
    if (!a.runfile.empty() || !a.outdir.empty() || !a.branch_dir.empty())
      throw capsim::ConfigError("--resume takes its options from the checkpoint: give no "
                                "RUNFILE, no -o and no --branch with it");
    request.resume = true;
    request.outdir = a.resume_dir;
    request.resume_overrides = a.sets;
  } else if (!a.branch_dir.empty()) {
    if (!a.runfile.empty() || a.outdir.empty())
      throw capsim::ConfigError("--branch takes its options from the checkpoint: give no "
                                "RUNFILE, and the new run's folder with -o");
    request.branch_from = a.branch_dir;
    request.outdir = a.outdir;
    request.resume_overrides = a.sets;
  } else {
    if (a.outdir.empty())
      throw capsim::ConfigError(
          "-o OUTDIR is required for a new run (or --resume OUTDIR)");
    request.options = capsim::load_run_options(a.runfile, a.sets);
    request.outdir = a.outdir;
  }
  request.pause_at = a.pause_at;
  capsim::RunProfile profile;
  if (!a.profile.empty())
    request.profile = &profile;
  const bool finished = capsim::run_simulation(request);
  if (!a.profile.empty())
    capsim::write_run_profile(a.profile, profile);
  if (!a.quiet && finished)
    std::fprintf(stderr, "capsim: done, see %s/summary.json\n", request.outdir.c_str());
  else if (!a.quiet)
    std::fprintf(stderr,
                 "capsim: paused at the checkpoint in %s (continue with --resume)\n",
                 request.outdir.c_str());
  return 0;
}

// Bad command lines end like every other bad input: one line `capsim: error: ...` that
// names the option, and exit code 2 (CLI11's own report is two lines with codes from
// 104 to 114). --help and --version keep CLI11's output and exit code 0.
int report_parse_error(const CLI::App& app, const CLI::ParseError& e) {
  if (e.get_exit_code() == 0)
    return app.exit(e);
  std::string what = e.what();
  if (dynamic_cast<const CLI::RequiredError*>(&e) && app.get_subcommands().empty()) {
    const std::vector<std::string> extra = app.remaining();
    what =
        (extra.empty() ? std::string("a command is required")
                       : "unknown command " + capsim::quoted_for_message(extra[0])) +
        ": run, params, greens, multipole-error, bench or selftest (see capsim --help)";
  }
  for (char& ch : what) // CLI11 repeats what was typed: keep the message one line
    if (static_cast<unsigned char>(ch) < 0x20)
      ch = ' ';
  std::fprintf(stderr, "capsim: error: %s\n", what.c_str());
  return kExitConfig;
}

} // namespace

int main(int argc, char** argv) {
  // Every evaluation of the flow allocates and frees megabytes of work arrays (triangle
  // loads, sources, pair buffers). Above its mmap threshold glibc hands such blocks back
  // to the kernel when freed, so each evaluation paid the page faults and the zeroing of
  // fresh pages again, 5-7 % of an evaluation at level 3 (docs/performance.md);
  // kept in the heap, the blocks are reused, for 2 % more peak memory.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  CLI::App app{"capsim " CAPSIM_VERSION
               ": neo-Hookean capsules in Stokes shear flow (boundary elements + FEM), "
               "after Matsunaga et al. (2016), J. Fluid Mech."};
  app.set_version_flag("--version", "capsim " CAPSIM_VERSION);
  app.require_subcommand(1);
  RunArgs run_args;
  add_run_command(app, run_args);
  ParamsArgs params_args;
  CLI::App* params = add_params_command(app, params_args);
  GreensArgs greens_args;
  add_greens_command(app, greens_args);
  MultipoleArgs multipole_args;
  add_multipole_command(app, multipole_args);
  BenchArgs bench_args;
  add_bench_command(app, bench_args);
  std::string selftest_backend = "cuda";
  add_selftest_command(app, selftest_backend);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return report_parse_error(app, e);
  }
  try {
    if (app.got_subcommand("selftest"))
      return capsim::run_backend_selftest(capsim::parse_backend(selftest_backend),
                                          std::cout)
                 ? 0
                 : kExitNumerical;
    if (app.got_subcommand("greens"))
      return greens_command(greens_args);
    if (app.got_subcommand("multipole-error"))
      return multipole_command(multipole_args);
    if (app.got_subcommand("bench"))
      return bench_command(bench_args);
    if (params->parsed())
      return params_command(params_args);
    return run_command(run_args);
  } catch (const capsim::ConfigError& e) {
    std::fprintf(stderr, "capsim: error: %s\n", e.what());
    return kExitConfig;
  } catch (const capsim::SimulationError& e) {
    std::fprintf(stderr, "capsim: error: %s\n", e.what());
    return kExitNumerical;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "capsim: error: %s\n", e.what());
    return kExitIo;
  }
}
