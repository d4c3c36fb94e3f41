// The CUDA backend as far as a machine without a GPU can check it: the host-device near
// corrections its kernels run, the clear refusal of backend: cuda, and the self-test's
// CPU-against-CPU path.
#include "config/run_options.hpp"
#include "cuda/device_flow.hpp"
#include "cuda/device_query.hpp"
#include "dynamics/cpu_flow.hpp"
#include "mesh/icosphere.hpp"
#include "run/backend_selftest.hpp"
#include "run/flow_factory.hpp"
#include "stokes/quadrature/near_corrections.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace capsim;

namespace {

// int_T J(x - y) q dA by brute force: 4^depth sub-triangles, 7 points each.
Vec3 fine_integral(Vec3 x, const TriangleLoad& t, int depth) {
  if (depth == 0)
    return integrate_regular(x, t, triangle_rule_7());
  Vec3 mp[3] = {0.5 * (t.p[0] + t.p[1]), 0.5 * (t.p[1] + t.p[2]),
                0.5 * (t.p[2] + t.p[0])};
  Vec3 mq[3] = {0.5 * (t.q[0] + t.q[1]), 0.5 * (t.q[1] + t.q[2]),
                0.5 * (t.q[2] + t.q[0])};
  const TriangleLoad kids[4] = {{{t.p[0], mp[0], mp[2]}, {t.q[0], mq[0], mq[2]}},
                                {{mp[0], t.p[1], mp[1]}, {mq[0], t.q[1], mq[1]}},
                                {{mp[2], mp[1], t.p[2]}, {mq[2], mq[1], t.q[2]}},
                                {{mp[0], mp[1], mp[2]}, {mq[0], mq[1], mq[2]}}};
  Vec3 sum;
  for (const auto& k : kids)
    sum += fine_integral(x, k, depth - 1);
  return sum;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

} // namespace

TEST_CASE("near corrections: the nearest-image correction plus the 3-point rule is the "
          "accurate integral of that image",
          "[cuda][hd]") {
  const TriangleLoad t{{{0, 0, 0}, {0.2, 0, 0}, {0.05, 0.18, 0.02}},
                       {{1, 0.5, -0.2}, {0.3, -1, 0.4}, {-0.6, 0.2, 1}}};
  const ShearedLattice g = make_sheared_lattice(3.0, 0.3);
  NearRule rule; // finer than the default, to test the formula rather than the rule
  rule.near_ratio = 4;
  rule.max_depth = 10;
  // A near-singular target beside the triangle, seen directly and through a lattice
  // image.
  const Vec3 x{0.08, 0.06, 0.05};
  const Vec3 want = fine_integral(x, t, 6);
  for (Vec3 shift : {Vec3{}, lattice_point(g, 1, -1, 2)}) {
    const Vec3 got = nearest_image_near_correction(g, x + shift, -1, t, rule) +
                     integrate_regular(x, t, triangle_rule_3());
    CHECK(norm(got - want) < 1e-6 * norm(want));
  }
  // A far image gets no correction.
  CHECK(norm(nearest_image_near_correction(g, x + Vec3{1.2, 0, 0}, -1, t, rule)) == 0);
}

TEST_CASE(
    "cuda backend: refused with a one-line error naming the key where it cannot run",
    "[cuda]") {
  const std::string reason = cuda_unavailable_reason();
  if (!reason.empty()) {
    const Icosphere mesh = make_icosphere(1);
    const Membrane membrane(mesh.topology, mesh.positions.data(), 1.0);
    CHECK_THROWS_WITH(check_flow_supported(Backend::cuda, {membrane}),
                      Catch::StartsWith("backend: cuda is not available here"));
    std::ostringstream out;
    CHECK_THROWS_AS(run_backend_selftest(Backend::cuda, out), ConfigError);
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "capsim_test_cuda_refused";
    fs::remove_all(dir);
    const std::string err = (dir.string() + ".err");
    const std::string cmd = std::string(CAPSIM_BINARY) + " run --set backend=cuda -o " +
                            dir.string() + " 2>" + err;
    const int status = std::system(cmd.c_str());
    CHECK(WEXITSTATUS(status) == 2);
    const std::string text = read_file(err);
    CHECK_THAT(text, Catch::StartsWith("capsim: error: backend: cuda"));
    CHECK(std::count(text.begin(), text.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(dir)); // nothing was written
    fs::remove(err);
  } else {
    CHECK(parse_run_options("backend: cuda\n", {}).backend == Backend::cuda);
  }
  CHECK(parse_run_options("backend: cpu\n", {}).backend == Backend::cpu);
}

TEST_CASE("cuda backend: what it lacks is refused by one check naming the key, whatever "
          "builds the flow",
          "[cuda]") {
  const Icosphere mesh = make_icosphere(1);
  const Membrane plain(mesh.topology, mesh.positions.data(), 1.0);
  const Membrane bent(mesh.topology, mesh.positions.data(), 1.0, 0.05);
  const FlowCapabilities device = DeviceFlow::capabilities();
  FlowSetup consistent{plain}, direct{plain}, repelled{plain}, wide{plain},
      spectral{plain}, single{plain}, single_real{plain};
  consistent.load = LoadMapping::consistent;
  direct.box = make_periodic_box(6.0, {EwaldMethod::direct, 1e-4}, 100, 300);
  repelled.repulsion.force = 5;
  wide.box = make_periodic_box(6.0, {EwaldMethod::spectral, 1e-4, 0.3}, 100, 300);
  // The automatic xi within the device's limit on r_cut, double grids (what a run asks of
  // the device when its precision is auto) and single ones (auto at 1e-4 on the CPU).
  EwaldOptions automatic{EwaldMethod::spectral, 1e-4};
  automatic.precision = automatic.real_space_precision = Precision::double_precision;
  spectral.box = make_periodic_box(6.0, automatic, 100, 300, device.max_cut_fraction);
  automatic.precision = Precision::automatic;
  single.box = make_periodic_box(6.0, automatic, 100, 300, device.max_cut_fraction);
  automatic.precision = Precision::double_precision;
  automatic.real_space_precision = Precision::automatic;
  single_real.box = make_periodic_box(6.0, automatic, 100, 300, device.max_cut_fraction);
  const std::vector<std::pair<FlowSetup, std::string>> refused = {
      {consistent, "membrane.load: must be lumped with backend: cuda"},
      {direct, "method: must be spectral with backend: cuda"},
      {wide, "ewald.xi: the real-space cut-off"},
      {single, "ewald.precision: must be double with backend: cuda"},
      {single_real, "ewald.real_space_precision: must be double with backend: cuda"}};
  for (const auto& [setup, message] : refused) {
    CHECK_THAT(unsupported_by(setup, device, Backend::cuda), Catch::StartsWith(message));
    CHECK(unsupported_by(setup, CpuFlow::capabilities(), Backend::cpu).empty());
  }
  CHECK(unsupported_by({plain}, device, Backend::cuda).empty());
  CHECK(unsupported_by(spectral, device, Backend::cuda).empty());
  // The repulsion runs on the device (its gradient from the host); a backend that lacked
  // it would be told so by the same check.
  CHECK(unsupported_by(repelled, device, Backend::cuda).empty());
  FlowCapabilities no_repulsion = device;
  no_repulsion.repulsion = false;
  CHECK_THAT(
      unsupported_by(repelled, no_repulsion, Backend::cuda),
      Catch::StartsWith("suspension.repulsion_force: must be 0 with backend: cuda"));
  // Bending runs on the device (its hinge kernel calls the CPU's hinge function); a
  // backend without it is told so by the same check.
  CHECK(unsupported_by({bent}, device, Backend::cuda).empty());
  FlowCapabilities no_bending = device;
  no_bending.bending = false;
  CHECK_THAT(unsupported_by({bent}, no_bending, Backend::cuda),
             Catch::StartsWith("membrane.bending: must be 0 with backend: cuda"));
  // The relaxed membrane runs on the device: its kernel calls the same element function.
  const Membrane wrinkling(mesh.topology, mesh.positions.data(), 1.0, 0, true);
  CHECK(unsupported_by({wrinkling}, device, Backend::cuda).empty());
}

TEST_CASE("selftest: the cpu backend agrees with itself", "[cuda]") {
  std::ostringstream out;
  CHECK(run_backend_selftest(Backend::cpu, out));
  INFO(out.str());
  CHECK_THAT(out.str(), Catch::Contains("periodic (spectral), 2 capsules: velocity") &&
                            Catch::Contains("wrinkling membrane: membrane traction") &&
                            Catch::Contains("2 capsules, repulsion: velocity") &&
                            Catch::Contains("bending, repulsion: positions after") &&
                            Catch::Contains("capsim selftest: passed"));
}
