// The adaptive step: the controller's rule, and a run whose first step is far too large
// (rejected and retried, samples still on their grid).
#include "dynamics/adaptive_step.hpp"
#include "dynamics/step_error.hpp"
#include "io/timeseries_file.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace capsim;
namespace fs = std::filesystem;

TEST_CASE("adaptive: the controller accepts within the tolerance and scales the step by "
          "(tolerance / error)^(1/2)",
          "[adaptive]") {
  StepController c;
  c.tolerance = 1e-3;
  CHECK(c.accept(1e-3));
  CHECK_FALSE(c.accept(1.1e-3));
  CHECK_FALSE(c.accept(std::nan("")));
  CHECK(c.next(0.1, 0.25e-3) == Approx(0.1 * 0.9 * 2.0));
  CHECK(c.next(0.1, 4e-3) == Approx(0.1 * 0.9 * 0.5));
  CHECK(c.next(0.1, 0) == Approx(0.2));             // bounded growth
  CHECK(c.next(0.1, 1.0) == Approx(0.02));          // bounded shrinking
  CHECK(c.next(0.1, std::nan("")) == Approx(0.02)); // a broken step shrinks most
  CHECK(c.next(0.1, HUGE_VAL) == Approx(0.02));
}

TEST_CASE("adaptive: the max norm is the largest node error, the rms norm the largest "
          "capsule's root mean square, and a NaN reaches the controller",
          "[adaptive]") {
  // Two capsules of four nodes: one node of the first is off by 0.4 (0.3, 0, 0.4 -> 0.5),
  // every node of the second by 0.3.
  std::vector<Vec3> e(8, Vec3{0.3, 0, 0});
  for (int i = 0; i < 4; ++i)
    e[i] = Vec3{0, 0, 0};
  e[2] = Vec3{0.3, 0, 0.4};
  CHECK(step_error(e, 2, ErrorNorm::max) == Approx(0.5));
  CHECK(step_error(e, 2, ErrorNorm::rms) == Approx(0.3)); // the first: 0.5 / 2 = 0.25
  CHECK(step_error(e, 1, ErrorNorm::rms) == Approx(std::sqrt((0.25 + 4 * 0.09) / 8)));
  e[5].y = std::nan("");
  CHECK(std::isnan(step_error(e, 2, ErrorNorm::max)));
  CHECK(std::isnan(step_error(e, 2, ErrorNorm::rms)));
  CHECK(parse_error_norm("rms") == ErrorNorm::rms);
  CHECK_THROWS_WITH(parse_error_norm("l2"),
                    Catch::Contains("time.error_norm") && Catch::Contains("{max, rms}"));
}

TEST_CASE("adaptive: a step far too large is rejected and retried, and samples stay on "
          "their grid",
          "[adaptive]") {
  const fs::path dir =
      fs::temp_directory_path() / ("capsim_test_adaptive_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  // dt = 0.5 is 25 times Heun's stability limit at level 2, Ca 0.2.
  const std::string cmd = std::string(CAPSIM_BINARY) +
                          " run -q --set mesh_level=2 --set ca=0.2 --set t_end=1.05 "
                          "--set t_avg_start=0.5 --set dt=0.5 --set time.tolerance=1e-3 "
                          "--set output.sample_interval=0.1 -o " +
                          dir.string();
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(dir / "summary.json");
  std::stringstream text;
  text << in.rdbuf();
  const std::string summary = text.str();
  const auto at = summary.find("\"rejected_steps\": ");
  REQUIRE(at != std::string::npos);
  CHECK(std::stol(summary.substr(at + 18)) > 0);
  const auto samples = read_timeseries((dir / "timeseries.h5").string());
  REQUIRE(samples.size() == 12); // 0, 0.1, ..., 1.0 and t_end
  for (size_t k = 0; k + 1 < samples.size(); ++k)
    CHECK(samples[k].time == k * 0.1);
  CHECK(samples.back().time == 1.05);
  fs::remove_all(dir);
}
