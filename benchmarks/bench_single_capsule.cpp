// Cost of one RK2 step for one capsule in shear at mesh levels 3 and 4, and where the
// time goes (membrane forces, quadrature set-up, dense far sum, near corrections). Prints
// one JSON object; run by benchmarks/run_benchmarks.sh. Aim (issue 2): level 4 below
// 0.25 s per step on 2 cores.
#include "dynamics/cpu_flow.hpp"
#include "dynamics/time_schemes.hpp"
#include "dynamics/volume_constraint.hpp"
#include "io/json_writer.hpp"
#include "mesh/surface_geometry.hpp"

#include <cmath>
#include <cstdio>
#include <omp.h>
#include <string>

using namespace capsim;

namespace {

// A deformed, capsule-like state: the sphere stretched along the extensional axis.
std::vector<Vec3> deformed(const std::vector<Vec3>& sphere) {
  const double c = std::cos(0.6), s = std::sin(0.6);
  std::vector<Vec3> x;
  for (const auto& p : sphere) {
    Vec3 q{1.3 * p.x, p.y / 1.14, p.z / 1.14};
    x.push_back({c * q.x - s * q.y, s * q.x + c * q.y, q.z});
  }
  return x;
}

void bench_level(JsonWriter& j, int level, int repeats) {
  Icosphere mesh = make_icosphere(level);
  Membrane membrane(mesh.topology, mesh.positions.data(), 1.0 / 0.2);
  QuadratureOptions quad;
  FlowSetup setup{membrane, 1, 1.0};
  setup.quadrature = quad;
  const CpuFlow flow(setup);
  std::vector<Vec3> x = deformed(mesh.positions), grad, q, u;

  double t0 = omp_get_wtime();
  for (int r = 0; r < repeats; ++r) {
    membrane.energy_gradient(x.data(), grad);
    membrane.nodal_load(x.data(), grad, LoadMapping::lumped, q);
  }
  double membrane_s = (omp_get_wtime() - t0) / repeats;
  SingleLayerTimings t;
  for (int r = 0; r < repeats; ++r)
    single_layer_velocity(mesh.topology, 1, x, q, quad, u, &t);
  std::vector<double> v0 = {enclosed_volume(mesh.topology, mesh.positions.data())};
  t0 = omp_get_wtime();
  for (int r = 0; r < repeats; ++r) {
    std::vector<Vec3> xs = x;
    heun_step(flow, xs, 0.0, 1e-3);
    enforce_volume(mesh.topology, 1, xs, v0);
  }
  double step_s = (omp_get_wtime() - t0) / repeats;

  j.begin_object(std::to_string(level));
  j.field("nodes", mesh.topology.num_nodes);
  j.field("triangles", long(mesh.topology.triangles.size()));
  j.field("seconds_per_step", step_s);
  j.field("seconds_membrane_per_eval", membrane_s);
  j.field("seconds_quadrature_setup_per_eval", t.setup / repeats);
  j.field("seconds_far_sum_per_eval", t.far / repeats);
  j.field("seconds_near_corrections_per_eval", t.near / repeats);
  j.field("near_pairs", t.near_pairs / repeats);
  j.field("far_pairs",
          long(mesh.topology.num_nodes) * 3 * long(mesh.topology.triangles.size()));
  j.end_object();
}

} // namespace

int main(int argc, char** argv) {
  int repeats = argc > 1 ? std::stoi(argv[1]) : 5;
  JsonWriter j;
  j.begin_object();
  j.field("benchmark", "single_capsule_rk2_step");
  j.field("threads", omp_get_max_threads());
  j.field("repeats", repeats);
  j.begin_object("levels");
  for (int level : {2, 3, 4})
    bench_level(j, level, repeats);
  j.end_object();
  j.end_object();
  std::fputs(j.str().c_str(), stdout);
}
