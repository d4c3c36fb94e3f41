// End-to-end tests of the capsim executable: a run killed with SIGKILL and resumed gives
// the same time series and summary as an uninterrupted run; bad input changes nothing.
#include "io/checkpoint_file.hpp"
#include "io/timeseries_file.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <signal.h>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace capsim;

namespace {

const std::vector<std::string> kCase = {"--set", "mesh_level=2",
                                        "--set", "ca=0.2",
                                        "--set", "t_end=3",
                                        "--set", "t_avg_start=1",
                                        "--set", "output.checkpoint_interval=0.1",
                                        "--set", "threads=1",
                                        "-q"};

fs::path fresh_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() /
               ("capsim_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

pid_t spawn(std::vector<std::string> args) {
  args.insert(args.begin(), CAPSIM_BINARY);
  pid_t pid = ::fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(CAPSIM_BINARY, argv.data());
    ::_exit(127);
  }
  return pid;
}

int run(const std::vector<std::string>& args) {
  int status = 0;
  ::waitpid(spawn(args), &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> with(std::vector<std::string> a,
                              const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// summary.json without the lines that legitimately differ (wall and CPU time, resumed
// flag, lambda != 1's GMRES counts).
std::string physics_of_summary(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  std::string line, out;
  while (std::getline(in, line))
    if (line.find("wall_seconds") == std::string::npos &&
        line.find("cpu_seconds") == std::string::npos &&
        line.find("\"resumed\"") == std::string::npos &&
        line.find("gmres_") == std::string::npos) // the solves of this invocation
      out += line + "\n";
  return out;
}

} // namespace

namespace {

// Runs `args` twice, once uninterrupted and once killed with SIGKILL after a checkpoint
// past step `kill_after` and then resumed; both must give the same summary and rows.
void check_kill_and_resume(const std::string& name, const std::vector<std::string>& args,
                           long kill_after) {
  fs::path whole = fresh_dir(name + "_whole"), killed = fresh_dir(name + "_killed");
  REQUIRE(run(with({"run", "-o", whole.string()}, args)) == 0);

  pid_t pid = spawn(with({"run", "-o", killed.string()}, args));
  for (int i = 0; i < 20000; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    try {
      if (read_checkpoint((killed / "checkpoint.h5").string()).step >= kill_after)
        break;
    } catch (const std::exception&) {
    }
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  REQUIRE(WIFSIGNALED(status));
  REQUIRE_FALSE(fs::exists(killed / "summary.json"));

  REQUIRE(run({"run", "-q", "--resume", killed.string()}) == 0);
  CHECK(physics_of_summary(killed) == physics_of_summary(whole));
  auto a = read_timeseries((whole / "timeseries.h5").string());
  auto b = read_timeseries((killed / "timeseries.h5").string());
  REQUIRE(a.size() == b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].time == b[i].time);
    for (size_t c = 0; c < a[i].capsules.size(); ++c) {
      CHECK(a[i].capsules[c].taylor_D == b[i].capsules[c].taylor_D);
      CHECK(a[i].capsules[c].stresslet.m[0][1] == b[i].capsules[c].stresslet.m[0][1]);
      CHECK(a[i].capsules[c].centroid.x == b[i].capsules[c].centroid.x);
    }
  }
  fs::remove_all(whole);
  fs::remove_all(killed);
}

} // namespace

TEST_CASE("resume: a killed and resumed run equals an uninterrupted one", "[resume]") {
  check_kill_and_resume("single", kCase, 20);
}

TEST_CASE("resume: a killed and resumed run with lambda != 1 equals an uninterrupted one",
          "[resume][lambda]") {
  // GMRES's first guess (the last evaluation's velocity) is not in the checkpoint: the
  // flow forgets it at every checkpoint, so both runs start each segment alike.
  check_kill_and_resume("lambda",
                        with(kCase, {"--set", "lambda=5", "--set", "t_end=1.5"}), 8);
}

TEST_CASE("resume: a killed and resumed suspension run equals an uninterrupted one",
          "[resume]") {
  // About 50 steps (dt ~0.12 at level 1), so the kill after step 12 lands mid-run and not
  // at its end, however fast the machine.
  check_kill_and_resume("suspension",
                        {"--set", "method=direct", "--set", "phi=0.05", "--set",
                         "capsules=2", "--set", "mesh_level=1", "--set", "t_end=6",
                         "--set", "t_avg_start=0.5", "--set",
                         "output.checkpoint_interval=0.1", "--set", "threads=1", "-q"},
                        12);
}

TEST_CASE("resume: a killed and resumed adaptive IMEX run equals an uninterrupted one",
          "[resume]") {
  // The step size to try next and the rejection count travel in the checkpoint.
  check_kill_and_resume(
      "adaptive",
      with(kCase, {"--set", "time.scheme=imex", "--set", "time.tolerance=1e-3", "--set",
                   "output.sample_interval=0.1"}),
      10);
}

TEST_CASE("resume: bad input is refused and loses nothing", "[resume]") {
  fs::path dir = fresh_dir("bad");
  REQUIRE(run({"run", "-q", "--set", "mesh_level=2", "--set", "t_end=0.2", "--set",
               "t_avg_start=0", "-o", dir.string()}) == 0);
  auto before = fs::last_write_time(dir / "summary.json");
  // A new run into a finished run's folder, a physics change on resume, bad values:
  CHECK(run({"run", "-q", "-o", dir.string()}) == 2);
  CHECK(run({"run", "-q", "--resume", dir.string(), "--set", "ca=0.5"}) == 2);
  CHECK(run({"run", "-q", "--set", "ca=-1", "-o", (dir / "sub").string()}) == 2);
  CHECK(fs::last_write_time(dir / "summary.json") == before);
  CHECK_FALSE(fs::exists(dir / "sub"));
  // A corrupt checkpoint is reported, not overwritten.
  { std::ofstream(dir / "checkpoint.h5") << "not an HDF5 file"; }
  CHECK(run({"run", "-q", "--resume", dir.string()}) == 4);
  std::ifstream in(dir / "checkpoint.h5");
  std::stringstream s;
  s << in.rdbuf();
  CHECK(s.str() == "not an HDF5 file");
  fs::remove_all(dir);
}

namespace {

std::string text_of(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

} // namespace

TEST_CASE("resume: a numerical blow-up stops with exit 3, keeps the checkpoint and says "
          "how the run ended",
          "[resume]") {
  fs::path dir = fresh_dir("blowup");
  // dt far above the stable ~0.5 Ca h: the membrane folds within a few steps.
  CHECK(run({"run", "-q", "--set", "mesh_level=2", "--set", "ca=0.05", "--set", "dt=0.2",
             "--set", "t_end=5", "--set", "t_avg_start=0", "-o", dir.string()}) == 3);
  Checkpoint c = read_checkpoint((dir / "checkpoint.h5").string());
  CHECK(c.step == 0);
  const std::string summary = text_of(dir / "summary.json");
  CHECK(summary.find("\"ended\": \"numerical\"") != std::string::npos);
  CHECK(summary.find("\"end_message\": \"numerical failure at gammadot*t") !=
        std::string::npos);
  fs::remove_all(dir);
}

namespace {

// Two capsules at phi 0.45 that come within 0.2 of each other near gammadot*t = 1.3
// (measured), with a contact stop at 0.2.
const std::vector<std::string> kClosePair = {"run",   "-q",
                                             "--set", "method=direct",
                                             "--set", "phi=0.45",
                                             "--set", "capsules=2",
                                             "--set", "mesh_level=1",
                                             "--set", "t_end=4",
                                             "--set", "t_avg_start=0",
                                             "--set", "suspension.min_gap=0.05",
                                             "--set", "suspension.stop_distance=0.2",
                                             "--set", "output.sample_interval=0.1",
                                             "--set", "output.checkpoint_interval=10",
                                             "--set", "threads=1"};

} // namespace

TEST_CASE("resume: a contact stop keeps the samples before it and records \"contact\"",
          "[resume]") {
  fs::path dir = fresh_dir("contact");
  // The run stops at the contact and keeps the samples taken before it.
  REQUIRE(run(with(kClosePair, {"-o", dir.string()})) == 3);
  const std::string summary = text_of(dir / "summary.json");
  CHECK(summary.find("\"ended\": \"contact\"") != std::string::npos);
  // The default tolerance, 1e-6, is summed in double; plain Ewald has no grid.
  CHECK(summary.find("\"real_space_precision\": \"double\"") != std::string::npos);
  CHECK(summary.find("spectral_precision") == std::string::npos);
  auto samples = read_timeseries((dir / "timeseries.h5").string());
  REQUIRE(samples.size() >= 5);
  CHECK(samples.back().time < 4.0);
  CHECK(summary.find("\"samples\": " + std::to_string(samples.size())) !=
        std::string::npos);
  // A resume starts again from the last checkpoint (here the initial state).
  CHECK(read_checkpoint((dir / "checkpoint.h5").string()).step == 0);
  fs::remove_all(dir);
}

TEST_CASE("resume: summary.json names the precision that `auto` took for each stage",
          "[resume]") {
  // Spectral Ewald at tolerance 1e-3 takes single precision for the grids and the
  // real-space sum (kSinglePrecisionTolerance 1e-5).
  fs::path dir = fresh_dir("precision");
  REQUIRE(run({"run", "-q", "--set", "phi=0.3", "--set", "capsules=2", "--set",
               "mesh_level=1", "--set", "t_end=0.1", "--set", "t_avg_start=0", "--set",
               "ewald.tolerance=1e-3", "--set", "threads=1", "-o", dir.string()}) == 0);
  const std::string summary = text_of(dir / "summary.json");
  CHECK(summary.find("\"spectral_precision\": \"single\"") != std::string::npos);
  CHECK(summary.find("\"real_space_precision\": \"single\"") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("resume: the same close pair with the repulsion on runs to its end and counts "
          "the samples in which it acted",
          "[resume][repulsion]") {
  fs::path dir = fresh_dir("repulsion");
  // As in the contact test, with a repulsion of range 0.4 a (force 5 mu gammadot a^2 at
  // contact): it holds the nodes apart beyond the stop distance 0.2 (measured: force 1
  // is too weak and stops by contact). To t = 3.5: in this box (L = 2.65) capsule 0 then
  // comes within 0.2 of its own periodic image (at 3.84, measured), which the repulsion,
  // between different capsules, does not act on.
  REQUIRE(run(with(kClosePair, {"--set", "suspension.repulsion_force=5", "--set",
                                "suspension.repulsion_range=0.4", "--set", "t_end=3.5",
                                "-o", dir.string()})) == 0);
  const std::string summary = text_of(dir / "summary.json");
  CHECK(summary.find("\"ended\": \"t_end\"") != std::string::npos);
  CHECK(summary.find("\"repelled_samples\": 0,") == std::string::npos);
  auto samples = read_timeseries((dir / "timeseries.h5").string());
  double repelled = 0;
  for (const auto& s : samples)
    for (const auto& c : s.capsules)
      repelled += c.repelled_nodes;
  CHECK(repelled > 0);
  fs::remove_all(dir);
}

namespace {

// The time series of a run folder and one column of it.
std::vector<Sample> series_of(const fs::path& dir) {
  return read_timeseries((dir / "timeseries.h5").string());
}

} // namespace

TEST_CASE("branch: a new run from another's checkpoint continues it, with the same "
          "numerics bit for bit and with others from the same state",
          "[resume][branch]") {
  fs::path whole = fresh_dir("branch_whole"), from = fresh_dir("branch_from"),
           same = fresh_dir("branch_same"), imex = fresh_dir("branch_imex"),
           halves = fresh_dir("branch_halves");
  REQUIRE(run(with({"run", "-o", whole.string()}, kCase)) == 0);
  REQUIRE(run(with({"run", "--pause-at", "1", "-o", from.string()}, kCase)) == 0);
  const Checkpoint start = read_checkpoint((from / "checkpoint.h5").string());
  const auto from_files = fs::last_write_time(from / "checkpoint.h5");

  // The same numerics: the uninterrupted run to the last bit.
  REQUIRE(run({"run", "-q", "--branch", from.string(), "-o", same.string()}) == 0);
  CHECK(physics_of_summary(same) == physics_of_summary(whole));
  const auto a = series_of(whole), b = series_of(same);
  REQUIRE(a.size() == b.size());
  for (size_t i = 0; i < a.size(); ++i)
    CHECK(a[i].capsules[0].taylor_D == b[i].capsules[0].taylor_D);

  // Adaptive IMEX from the fixed Heun step's checkpoint: the rows before it are the
  // source's, the samples go on every 0.05 from it (its grid is the fixed step's, which
  // counts steps), and a branch paused and resumed equals the unbroken one.
  const std::vector<std::string> other = {"--set", "time.scheme=imex", "--set",
                                          "time.tolerance=1e-3"};
  REQUIRE(run(with({"run", "-q", "--branch", from.string(), "-o", imex.string()},
                   other)) == 0);
  REQUIRE(run(with({"run", "-q", "--pause-at", "2", "--branch", from.string(), "-o",
                    halves.string()},
                   other)) == 0);
  REQUIRE(run({"run", "-q", "--resume", halves.string()}) == 0);
  const auto c = series_of(imex), h = series_of(halves);
  const long n = long(start.samples_written);
  REQUIRE(long(c.size()) > n);
  for (long i = 0; i < n; ++i)
    CHECK(c[i].capsules[0].taylor_D == a[i].capsules[0].taylor_D);
  CHECK(c[n].time == Approx(start.time + 0.05).epsilon(1e-12));
  CHECK(c.back().time == 3.0);
  REQUIRE(c.size() == h.size());
  for (size_t i = 0; i < c.size(); ++i)
    CHECK(c[i].capsules[0].taylor_D == h[i].capsules[0].taylor_D);
  // Both follow one trajectory: at gammadot t = 3 (the fixed step's last sample at 3.05,
  // where D has settled to within 1e-4) they differ by far less than the scheme's step
  // tolerance of 1e-3 a on the nodes (8e-6 measured).
  CHECK(std::abs(c.back().capsules[0].taylor_D - a.back().capsules[0].taylor_D) < 1e-3);

  // The model cannot change; the source is never written.
  CHECK(run({"run", "-q", "--branch", from.string(), "-o", (from / "x").string(), "--set",
             "ca=0.5"}) == 2);
  CHECK(run({"run", "-q", "--branch", from.string()}) == 2);
  CHECK(run({"run", "-q", "--branch", from.string(), "-o", imex.string()}) == 2);
  CHECK(fs::last_write_time(from / "checkpoint.h5") == from_files);
  CHECK_FALSE(fs::exists(from / "x"));
  for (const auto& d : {whole, from, same, imex, halves})
    fs::remove_all(d);
}

TEST_CASE("branch: another fixed step counts its steps from the checkpoint's time, and "
          "paused and resumed it equals the unbroken branch",
          "[resume][branch]") {
  fs::path from = fresh_dir("step_from"), whole = fresh_dir("step_whole"),
           halves = fresh_dir("step_halves");
  REQUIRE(run(with({"run", "--pause-at", "1", "-o", from.string()}, kCase)) == 0);
  const Checkpoint start = read_checkpoint((from / "checkpoint.h5").string());
  // Half the source's step: 0.5 Ca h is no multiple of the source's step's time.
  const std::vector<std::string> half = {"--set", "dt_safety=0.5"};
  REQUIRE(run(with({"run", "-q", "--branch", from.string(), "-o", whole.string()},
                   half)) == 0);
  REQUIRE(run(with({"run", "-q", "--pause-at", "2", "--branch", from.string(), "-o",
                    halves.string()},
                   half)) == 0);
  const Checkpoint paused = read_checkpoint((halves / "checkpoint.h5").string());
  CHECK(paused.step_origin_index == start.step);
  CHECK(paused.step_origin_time == start.time);
  REQUIRE(run({"run", "-q", "--resume", halves.string()}) == 0);

  const auto w = series_of(whole), h = series_of(halves);
  const long n = long(start.samples_written);
  REQUIRE(long(w.size()) > n + 1);
  // Every row after the checkpoint lies on the new grid, start + k dt, with the step
  // from the two first rows after it; sample spacing is the nearest whole number of
  // steps to 0.05, and the last row is the first step at or past t_end = 3.
  const double dt = (w[n + 1].time - w[n].time) / double(w[n + 1].step - w[n].step);
  CHECK(w[n].time > start.time);
  CHECK(w[n].time - start.time == Approx(0.05).margin(dt / 2));
  for (long i = n; i < long(w.size()); ++i)
    CHECK(w[i].time ==
          Approx(start.time + double(w[i].step - start.step) * dt).epsilon(1e-13));
  CHECK(w.back().time >= 3.0);
  CHECK(w.back().time < 3.0 + dt);
  REQUIRE(w.size() == h.size());
  for (size_t i = 0; i < w.size(); ++i) {
    CHECK(w[i].time == h[i].time);
    CHECK(w[i].capsules[0].taylor_D == h[i].capsules[0].taylor_D);
  }
  for (const auto& d : {from, whole, halves})
    fs::remove_all(d);
}

TEST_CASE("resume: an adaptive run resumed with another sample interval samples on from "
          "its checkpoint",
          "[resume]") {
  // Its samples were at k 0.05; at 0.03 from the checkpoint at 1 the next is at 1.03, not
  // at k 0.03 for the k-th row, which lies before the checkpoint (the step would be < 0).
  fs::path dir = fresh_dir("interval");
  REQUIRE(run(with({"run", "--pause-at", "1", "-o", dir.string()},
                   with(kCase, {"--set", "time.scheme=imex", "--set",
                                "time.tolerance=1e-3", "--set", "t_end=1.5"}))) == 0);
  REQUIRE(run({"run", "-q", "--resume", dir.string(), "--set",
               "output.sample_interval=0.03"}) == 0);
  const auto s = series_of(dir);
  REQUIRE(s.size() == 21 + 17); // 0 to 1 by 0.05, then 1.03 to 1.48 by 0.03, and 1.5
  CHECK(s[21].time == Approx(1.03).epsilon(1e-12));
  CHECK(s.back().time == 1.5);
  fs::remove_all(dir);
}

TEST_CASE("cli: capsim greens prints the periodic Stokeslet and refuses lattice points",
          "[cli]") {
  fs::path out = fresh_dir("greens");
  std::string cmd = std::string(CAPSIM_BINARY) +
                    " greens --box 4 --strain 1.3 --point 0.7 -1.3 0.4 > " + out.string();
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(out);
  std::stringstream s;
  s << in.rdbuf();
  CHECK_THAT(s.str(), Catch::Contains("\"J\": [[-0.0345848158") &&
                          Catch::Contains("\"strain\": 0.3"));
  CHECK(run({"greens", "--box", "4", "--point", "4", "0", "0"}) == 2);
  fs::remove(out);
}

TEST_CASE("cli: capsim bench prints its JSON with the error against the reference, and "
          "refuses bad options",
          "[cli]") {
  fs::path out = fresh_dir("bench");
  std::string cmd = std::string(CAPSIM_BINARY) +
                    " bench --capsules 2 --mesh-level 1 --phi 0.2 --tolerance 1e-3 "
                    "--repeats 1 --threads 1 > " +
                    out.string();
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(out);
  std::stringstream s;
  s << in.rdbuf();
  CHECK_THAT(s.str(), Catch::Contains("\"seconds_per_eval\"") &&
                          Catch::Contains("\"rel_error\"") &&
                          Catch::Contains("\"spreading\"") &&
                          Catch::Contains("\"sources\": 480"));
  // The error at tolerance 1e-3 is below it (against direct Ewald at 1e-10).
  const std::string text = s.str();
  const double error = std::stod(text.substr(text.find("\"rel_error\": ") + 13));
  CHECK(error < 1e-3);
  CHECK(run({"bench", "--phi", "0.9"}) == 2);
  CHECK(run({"bench", "--method", "multipole"}) == 2);
  CHECK(run({"bench", "--method", "patches", "--mesh-level", "1", "--patch-level",
             "2"}) == 2);
  fs::remove(out);
}
