#include "run/run_plan.hpp"

#include "common/suspension.hpp"
#include "mesh/surface_geometry.hpp"
#include "run/automatic_settings.hpp"
#include "run/flow_factory.hpp"
#include "stokes/quadrature/triangle_sources.hpp"

#include <algorithm>
#include <cmath>

namespace capsim {

namespace {

// The automatic step of the run's scheme: Heun's (automatic_time_step) times how much
// longer a step the scheme's stability allows (rkc: beta(s) / 2).
// The explicit step's limit is the relaxation of the mesh-scale membrane waves, whose
// rate goes as 1/(mu (1 + lambda)) (the outer and inner fluid resist a short wave in
// series: the factor 2/(1 + lambda) of f in second_kind_solve.hpp). With lambda < 1 the
// step shrinks by (1 + lambda)/2 to keep its margin. With lambda > 1 it may grow as much
// (one capsule at Ca 0.05-0.6: Heun stable at 1.5 and unstable at 2 times lambda 1's
// step at lambda 1, at 3 and 4.5 times at lambda 5), but the slow motion's time error
// grows as dt^2, so only up to dt_lambda_max, by default 1 (docs/time_stepping.md, "The
// step at lambda > 1"). At lambda = 1 the factor is exactly 1.
double viscous_factor(const RunOptions& o) {
  const double relax = 0.5 * (1 + o.lambda);
  return o.lambda < 1 ? relax : std::min(relax, o.dt_lambda_max);
}

double automatic_step(const RunOptions& o, double h) {
  return automatic_time_step(o.ca, h, o.dt_safety, o.bending) *
         stability_ratio(o.time.scheme, o.time.stages) * viscous_factor(o);
}

TimePlan time_plan(const RunOptions& o, double h) {
  TimePlan t;
  t.scheme = o.time.scheme;
  t.stages = o.time.stages;
  t.norm = o.time.error_norm;
  t.tolerance = o.time.tolerance;
  const double automatic = automatic_step(o, h);
  t.dt = o.dt > 0 ? o.dt : automatic;
  // An adaptive step a millionth of the automatic one means a broken state.
  t.min_dt = 1e-6 * automatic;
  t.t_end = o.t_end;
  return t;
}

long every(double interval, double unit) {
  return interval > 0 ? std::max(1L, std::lround(interval / unit)) : 0;
}

// Checkpoints and snapshots are written at samples only (run_outputs.cpp), so with a
// fixed step they come every so many samples: counted in steps on their own (the nearest
// count to their interval), a count that is not a multiple of the samples' would meet a
// sample only at the counts' least common multiple (a checkpoint every 11 strains, no
// snapshot after the first, at dt 0.0045).
OutputPlan output_plan(const OutputOptions& out, const TimePlan& t) {
  const double unit = t.fixed() ? t.dt : out.sample_interval;
  const long sample = every(out.sample_interval, unit); // > 0: sample_interval > 0
  const double per_sample = double(sample) * unit;
  return {sample, sample * every(out.checkpoint_interval, per_sample),
          sample * every(out.snapshot_interval, per_sample)};
}

// The box for phi > 0 (docs/conventions.md); none (L = 0) in the dilute limit.
PeriodicBox run_box(const RunOptions& o, const Topology& topo, Backend backend) {
  if (o.phi <= 0)
    return {};
  return plan_periodic_box(periodic_box_side(o.capsules, o.phi), o.ewald,
                           capabilities_of(backend), long(o.capsules) * topo.num_nodes,
                           far_rule_points(topo, o.capsules), "ewald.xi");
}

} // namespace

PeriodicBox plan_periodic_box(double L, EwaldOptions request,
                              const FlowCapabilities& caps, long nodes, long points,
                              const std::string& xi_key) {
  request.precision =
      resolve_precision(request.precision, request.tolerance, caps.single_grids);
  request.real_space_precision = resolve_precision(
      request.real_space_precision, request.tolerance, caps.single_real_space);
  try {
    return make_periodic_box(L, request, nodes, points, caps.max_cut_fraction);
  } catch (const std::invalid_argument& e) { // a given xi out of proportion to the box
    throw ConfigError(xi_key + ": " + e.what());
  }
}

RunPlan resolve_run_plan(const RunOptions& options, bool quiet) {
  RunPlan p;
  p.options = options;
  resolve_automatic_settings(p.options, quiet);
  const RunOptions& o = p.options;
  p.mesh = make_icosphere(o.mesh_level);
  p.mean_edge = mean_edge_length(p.mesh.topology, p.mesh.positions.data());
  p.backend = o.backend;
  p.time = time_plan(o, p.mean_edge);
  p.output = output_plan(o.output, p.time);
  p.box = run_box(o, p.mesh.topology, p.backend);
  return p;
}

FlowSetup flow_setup(const RunPlan& plan, const Membrane& membrane) {
  const RunOptions& o = plan.options;
  FlowSetup s(membrane, o.capsules, o.flow == "shear" ? 1.0 : 0.0);
  s.load = o.load;
  s.quadrature = o.quadrature;
  s.box = plan.box;
  s.repulsion = o.suspension.repulsion;
  s.lambda = o.lambda;
  s.gmres_tolerance = o.gmres_tolerance;
  s.gmres_guess = o.gmres_guess;
  return s;
}

} // namespace capsim
