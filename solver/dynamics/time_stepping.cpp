#include "dynamics/time_stepping.hpp"

#include "cuda/device_flow.hpp"
#include "mesh/surface_geometry.hpp"
#include "stokes/ewald_reciprocal.hpp"
#include "stokes/periodic_single_layer.hpp"

#include <cmath>
#include <sstream>

namespace capsim {

PeriodicBox make_periodic_box(double L, const std::string& method, double tolerance,
                              double xi, long nodes, long points, int patch_level) {
  PeriodicBox box;
  box.L = L;
  box.spectral = method == "spectral";
  // Patches keep the xi that balances equal per-term costs for all quadrature points:
  // balancing for their fewer sources, or for the cheaper reciprocal terms as `direct`
  // does, would raise xi and with it the coarse-graining error, which grows like
  // (xi d)^2 for patches of diameter d.
  if (method == "patches")
    box.patch_level = patch_level;
  if (xi <= 0)
    xi = box.spectral          ? spectral_xi(L, tolerance, nodes, points)
         : method == "patches" ? balanced_xi(L, tolerance, nodes, points)
                               : balanced_xi(L, tolerance, nodes, points, kRealPairCost);
  box.ewald = choose_ewald_parameters(L, tolerance, xi);
  if (box.spectral)
    box.grid = choose_spectral_parameters(L, box.ewald, tolerance);
  return box;
}

Backend parse_backend(const std::string& name) {
  if (name == "cpu")
    return Backend::cpu;
  if (name == "cuda")
    return Backend::cuda;
  throw std::invalid_argument("backend must be one of {cpu, cuda}, got '" + name + "'");
}

std::string to_string(Backend b) {
  return b == Backend::cpu ? "cpu" : "cuda";
}

CapsuleFlow::CapsuleFlow(const Membrane& membrane, int num_capsules, double shear_rate,
                         LoadMapping load, QuadratureOptions quadrature, PeriodicBox box,
                         Backend backend)
    : membrane_(membrane), num_capsules_(num_capsules), shear_rate_(shear_rate),
      load_(load), quadrature_(quadrature), box_(box) {
  if (backend == Backend::cuda)
    device_ = std::make_shared<DeviceFlow>(membrane, num_capsules, shear_rate, load,
                                           quadrature, box);
  else if (box_.L > 0 && box_.spectral)
    spectral_ = std::make_shared<SpectralEwald>(box_.L, box_.ewald, box_.grid);
}

std::vector<double> CapsuleFlow::energy_gradient(const std::vector<Vec3>& x,
                                                 std::vector<Vec3>& grad) const {
  const int nn = membrane_.topology().num_nodes;
  grad.resize(x.size());
  std::vector<double> energy(num_capsules_);
  std::vector<Vec3> g;
  for (int c = 0; c < num_capsules_; ++c) {
    energy[c] = membrane_.energy_gradient(&x[c * nn], g);
    std::copy(g.begin(), g.end(), grad.begin() + c * nn);
  }
  return energy;
}

void CapsuleFlow::set_repulsion(const RepulsionOptions& r) {
  if (r.on() && device_)
    throw std::invalid_argument("the repulsion between capsules runs on the CPU only");
  repulsion_ = r;
}

std::vector<int> CapsuleFlow::add_repulsion(const std::vector<Vec3>& x, double t,
                                            std::vector<Vec3>& grad) const {
  std::vector<int> count(num_capsules_, 0);
  if (repulsion_.on() && periodic())
    add_repulsion_gradient(lattice(t), membrane_.topology().num_nodes, x, repulsion_,
                           grad, &count);
  return count;
}

void CapsuleFlow::traction(const std::vector<Vec3>& x, double t,
                           std::vector<Vec3>& q) const {
  if (device_)
    return device_->traction(x, q);
  const int nn = membrane_.topology().num_nodes;
  std::vector<Vec3> grad, qc;
  q.resize(x.size());
  energy_gradient(x, grad);
  add_repulsion(x, t, grad);
  for (int c = 0; c < num_capsules_; ++c) {
    std::vector<Vec3> gc(grad.begin() + c * nn, grad.begin() + (c + 1) * nn);
    membrane_.nodal_load(&x[c * nn], gc, load_, qc);
    std::copy(qc.begin(), qc.end(), q.begin() + c * nn);
  }
}

void CapsuleFlow::velocity(const std::vector<Vec3>& x, double t,
                           std::vector<Vec3>& u) const {
  if (device_)
    return device_->velocity(x, t, u);
  const Topology& topo = membrane_.topology();
  std::vector<Vec3> q;
  traction(x, t, q);
  if (periodic())
    periodic_single_layer_velocity(topo, num_capsules_, x, q, lattice(t), box_.ewald,
                                   quadrature_, u, {spectral_.get(), box_.patch_level});
  else
    single_layer_velocity(topo, num_capsules_, x, q, quadrature_, u);
  for (size_t i = 0; i < x.size(); ++i)
    u[i].x += shear_rate_ * x[i].y;
}

void rk2_step(const CapsuleFlow& flow, std::vector<Vec3>& x, double t, double dt) {
  if (flow.device())
    return flow.device()->rk2_step(x, t, dt);
  std::vector<Vec3> u0, u1, xs(x.size());
  flow.velocity(x, t, u0);
  for (size_t i = 0; i < x.size(); ++i)
    xs[i] = x[i] + dt * u0[i];
  flow.velocity(xs, t + dt, u1);
  for (size_t i = 0; i < x.size(); ++i)
    x[i] += (0.5 * dt) * (u0[i] + u1[i]);
}

std::vector<double> enforce_volume(const Topology& topo, int num_capsules,
                                   std::vector<Vec3>& x,
                                   const std::vector<double>& volume0) {
  const int nn = topo.num_nodes;
  std::vector<double> drift(num_capsules);
  for (int c = 0; c < num_capsules; ++c) {
    Vec3* xc = &x[c * nn];
    for (int pass = 0; pass < 8; ++pass) {
      double v = enclosed_volume(topo, xc);
      double err = (v - volume0[c]) / volume0[c];
      if (pass == 0)
        drift[c] = err;
      if (std::abs(err) < 1e-13)
        break;
      double shift = (volume0[c] - v) / surface_area(topo, xc);
      std::vector<Vec3> n = node_normals(topo, xc);
      for (int i = 0; i < nn; ++i)
        xc[i] += shift * n[i];
    }
  }
  return drift;
}

void check_state(const Topology& topo, int num_capsules, const std::vector<Vec3>& x,
                 double time, double max_extent) {
  const int nn = topo.num_nodes;
  auto fail = [&](const std::string& what, int c) {
    std::ostringstream s;
    s << "numerical failure at gammadot*t = " << time << " in capsule " << c << ": "
      << what
      << ". The time step is probably too large for this Ca and mesh: start again "
         "with a smaller dt or dt_safety (the output folder keeps the last good "
         "checkpoint and time series)";
    throw SimulationError(s.str());
  };
  for (int c = 0; c < num_capsules; ++c) {
    const Vec3* xc = &x[c * nn];
    for (int i = 0; i < nn; ++i)
      if (!std::isfinite(xc[i].x) || !std::isfinite(xc[i].y) || !std::isfinite(xc[i].z))
        fail("a node position is not finite (NaN or Inf)", c);
    Vec3 centre = volume_centroid(topo, xc);
    for (int i = 0; i < nn; ++i)
      if (norm(xc[i] - centre) > max_extent)
        fail("the membrane has blown up", c);
    // A folded-over triangle points against the averaged normals of its own nodes.
    std::vector<Vec3> n = node_normals(topo, xc);
    for (const auto& t : topo.triangles) {
      Vec3 an = area_vector2(xc[t[0]], xc[t[1]], xc[t[2]]);
      if (dot(an, n[t[0]] + n[t[1]] + n[t[2]]) <= 0)
        fail("a surface triangle has inverted", c);
    }
  }
}

double automatic_time_step(double ca, double mean_edge, double safety, double bending) {
  return safety * ca * mean_edge / (1 + 4 * bending / (mean_edge * mean_edge));
}

} // namespace capsim
