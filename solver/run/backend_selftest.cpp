#include "run/backend_selftest.hpp"

#include "common/suspension.hpp"
#include "config/run_options.hpp"
#include "cuda/device_query.hpp"
#include "dynamics/time_schemes.hpp"
#include "mesh/surface_geometry.hpp"
#include "run/flow_factory.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

namespace capsim {
namespace {

// max_i |a_i - b_i| / max_i |b_i|
double max_relative_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double diff = 0, size = 0;
  for (size_t i = 0; i < b.size(); ++i) {
    diff = std::max(diff, norm(a[i] - b[i]));
    size = std::max(size, norm(b[i]));
  }
  return size > 0 ? diff / size : diff;
}

// A level-2 capsule (320 triangles) stretched and tilted, so that the membrane is loaded
// and nothing is symmetric, centred at c.
std::vector<Vec3> deformed_capsule(const Icosphere& mesh, Vec3 c, double stretch) {
  std::vector<Vec3> x;
  const double ct = std::cos(0.3), st = std::sin(0.3);
  for (const Vec3& p : mesh.positions) {
    const Vec3 q{stretch * p.x, p.y / std::sqrt(stretch), (1 + 0.05 * p.x) * p.z};
    x.push_back(c + Vec3{ct * q.x - st * q.y, st * q.x + ct * q.y, q.z});
  }
  return x;
}

// Two capsules in a sheared box at phi = 0.1, Spectral Ewald at tolerance 1e-6 with the
// automatic xi, raised to keep r_cut below L/5.5: the device needs it below L/3 and sums
// through cell bins (5 per side at least) only below L/5, which the test should cover.
PeriodicBox selftest_box(const Topology& topo) {
  const int capsules = 2;
  return make_periodic_box(periodic_box_side(capsules, 0.1), EwaldOptions{},
                           capsules * topo.num_nodes, far_rule_points(topo, capsules),
                           1 / 5.5);
}

struct Report {
  std::ostream& out;
  bool passed = true;
  void line(const std::string& what, double diff, double limit) {
    const bool ok = diff <= limit;
    passed = passed && ok;
    char buf[160];
    std::snprintf(buf, sizeof buf, "  %-52s %9.2e  (limit %.0e)  %s\n", what.c_str(),
                  diff, limit, ok ? "ok" : "FAILED");
    out << buf;
  }
};

// The reference (CPU) and candidate flows of one case, compared on evaluations and steps.
// repulsion: between the capsules (off by default); a case with it on must have nodes
// within its range, or it tests nothing.
void compare_case(Report& r, const std::string& name, const Membrane& membrane,
                  int capsules, const PeriodicBox& box, Backend backend,
                  const std::vector<Vec3>& x0, double dt, int steps,
                  RepulsionOptions repulsion = {}) {
  FlowSetup setup{membrane, capsules};
  setup.box = box;
  setup.repulsion = repulsion;
  const std::unique_ptr<Flow> cpu = make_flow(Backend::cpu, setup);
  const std::unique_ptr<Flow> other = make_flow(backend, setup);
  std::vector<Vec3> a, b;
  if (repulsion.on()) {
    std::vector<Vec3> grad(x0.size());
    const std::vector<int> repelled = cpu->add_repulsion(x0, 0.0, grad);
    int count = 0;
    for (int n : repelled)
      count += n;
    r.line(name + ": no node within the repulsion's range", count == 0, 0);
  }
  cpu->traction(x0, 0.0, a);
  other->traction(x0, 0.0, b);
  r.line(name + ": membrane traction", max_relative_difference(b, a), 1e-12);
  cpu->velocity(x0, 0.3, a);
  other->velocity(x0, 0.3, b);
  // Summation order differs (simd reductions, atomics in spreading, cuFFT against FFTW).
  r.line(name + ": velocity", max_relative_difference(b, a), 1e-10);
  std::vector<Vec3> xa = x0, xb = x0;
  for (int s = 0; s < steps; ++s) {
    heun_step(*cpu, xa, s * dt, dt);
    heun_step(*other, xb, s * dt, dt);
  }
  r.line(name + ": positions after " + std::to_string(steps) + " RK2 steps",
         max_relative_difference(xb, xa), 1e-10);
}

} // namespace

bool run_backend_selftest(Backend backend, std::ostream& out) {
  if (backend == Backend::cuda) {
    const std::string reason = cuda_unavailable_reason();
    if (!reason.empty())
      throw ConfigError("--backend cuda: " + reason);
    out << "capsim selftest: backend cuda (" << cuda_device_description()
        << ") against the cpu backend\n";
  } else {
    out << "capsim selftest: backend cpu against itself"
        << (cuda_backend_compiled() ? "" : " (this build has no CUDA backend)") << "\n";
  }
  const Icosphere mesh = make_icosphere(2);
  const double ca = 0.2, h = mean_edge_length(mesh.topology, mesh.positions.data());
  const Membrane membrane(mesh.topology, mesh.positions.data(), 1.0 / ca);
  const double dt = automatic_time_step(ca, h, 0.5);
  Report r{out};
  compare_case(r, "free space, 1 capsule", membrane, 1, {}, backend,
               deformed_capsule(mesh, {0, 0, 0}, 1.3), dt, 10);
  // Squashed along x: wrinkled about the equator, taut at the poles (tension_field.hpp).
  const Membrane wrinkling(mesh.topology, mesh.positions.data(), 1.0 / ca, 0, true);
  compare_case(r, "free space, 1 capsule, wrinkling membrane", wrinkling, 1, {}, backend,
               deformed_capsule(mesh, {0, 0, 0}, 0.8), dt, 10);
  const PeriodicBox box = selftest_box(mesh.topology);
  std::vector<Vec3> x = deformed_capsule(mesh, {1.0, 1.0, 1.0}, 1.2);
  for (const Vec3& p : deformed_capsule(mesh, {3.0, 2.5, 2.2}, 1.1))
    x.push_back(p);
  compare_case(r, "periodic (spectral), 2 capsules", membrane, 2, box, backend, x, dt, 3);
  // The second capsule just above the first: their poles 0.05 apart, within the range of
  // the dense suspensions' repulsion (0.1), at F0 = 5.
  std::vector<Vec3> close = deformed_capsule(mesh, {1.0, 1.0, 1.0}, 1.2);
  for (const Vec3& p : deformed_capsule(mesh, {1.0, 1.0, 3.05}, 1.1))
    close.push_back(p);
  compare_case(r, "periodic (spectral), 2 capsules, repulsion", membrane, 2, box, backend,
               close, dt, 3, RepulsionOptions{0.1, 5.0});
  // The grid's bending points: eb 0.025 (kb = eb Gs a^2) with the repulsion.
  const double eb = 0.025;
  const Membrane bending(mesh.topology, mesh.positions.data(), 1.0 / ca, eb / ca);
  compare_case(r, "periodic (spectral), 2 capsules, bending, repulsion", bending, 2, box,
               backend, close, automatic_time_step(ca, h, 0.5, eb), 3,
               RepulsionOptions{0.1, 5.0});
  out << "capsim selftest: " << (r.passed ? "passed" : "FAILED") << "\n";
  return r.passed;
}

} // namespace capsim
