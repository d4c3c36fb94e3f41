#include "dynamics/cpu_flow.hpp"

#include "dynamics/simulation_error.hpp"
#include "dynamics/state_checks.hpp"
#include "stokes/double_layer/second_kind_solve.hpp"

#include <algorithm>
#include <omp.h>
#include <sstream>
#include <stdexcept>

namespace capsim {
namespace {

// v += sign u_inf(x) at the nodes, u_inf = (shear_rate y, 0, 0) the imposed shear.
void add_shear_flow(const std::vector<Vec3>& x, double shear_rate, double sign,
                    std::vector<Vec3>& v) {
  for (size_t i = 0; i < x.size(); ++i)
    v[i].x += sign * shear_rate * x[i].y;
}

} // namespace

CpuFlow::CpuFlow(const FlowSetup& setup) : Flow(setup), history_(setup.gmres_guess) {
  const PeriodicBox& box = setup_.box;
  if (box.L > 0 && box.method == EwaldMethod::spectral)
    spectral_ = std::make_unique<SpectralEwald>(box.L, box.ewald, box.grid);
}

void CpuFlow::traction(const std::vector<Vec3>& x, double t, std::vector<Vec3>& q) const {
  const int nn = membrane().topology().num_nodes;
  std::vector<Vec3> grad, qc;
  q.resize(x.size());
  energy_gradient(x, grad);
  add_repulsion(x, t, grad);
  for (int c = 0; c < num_capsules(); ++c) {
    std::vector<Vec3> gc(grad.begin() + c * nn, grad.begin() + (c + 1) * nn);
    membrane().nodal_load(&x[c * nn], gc, setup_.load, qc);
    std::copy(qc.begin(), qc.end(), q.begin() + c * nn);
  }
}

// The single-layer kernels sum every node's traction into every velocity: one NaN in
// their input makes all of u NaN. Both ends are checked (O(N) against the kernels'
// O(N^2)) so that the message names where it began.
void CpuFlow::evaluate_velocity(const std::vector<Vec3>& x, double t,
                                std::vector<Vec3>& u) const {
  if (setup_.lambda != 1 && output_velocity_fits(x, t)) {
    u = output_.u;
    remember(x, t, u);
    output_.x.clear();
    return;
  }
  const Topology& topo = membrane().topology();
  std::vector<Vec3> q;
  require_finite(x, topo.num_nodes, "position", t);
  const double t0 = omp_get_wtime();
  traction(x, t, q);
  const double t1 = omp_get_wtime();
  require_finite(q, topo.num_nodes, "membrane traction", t);
  if (periodic())
    periodic_single_layer_velocity(topo, num_capsules(), x, q, lattice(t),
                                   setup_.box.ewald, setup_.quadrature, u,
                                   reciprocal_sum(setup_.box, spectral_.get()),
                                   profile_ ? &profile_->periodic : nullptr);
  else
    single_layer_velocity(topo, num_capsules(), x, q, setup_.quadrature, u);
  if (profile_) {
    profile_->traction += t1 - t0;
    if (!periodic())
      profile_->unbounded += omp_get_wtime() - t1;
  }
  add_shear_flow(x, setup_.shear_rate, 1, u);
  if (setup_.lambda != 1) // at lambda = 1 u is the solution itself: no solve
    solve_viscosity_ratio(x, t, u);
  require_finite(u, topo.num_nodes, "velocity", t);
}

void CpuFlow::output_velocity(const std::vector<Vec3>& x, double t,
                              std::vector<Vec3>& u) const {
  const GuessHistory before = history_;
  velocity(x, t, u);
  history_ = before;
  if (setup_.lambda != 1)
    output_ = {x, before, u, t};
}

// Whether the output's velocity is what an evaluation at (x, t) would compute now: the
// same state and the same guess history.
bool CpuFlow::output_velocity_fits(const std::vector<Vec3>& x, double t) const {
  return !output_.x.empty() && t == output_.t && x == output_.x &&
         history_ == output_.history;
}

// u_inf + u_SL in u on entry; on exit the surface velocity of capsules of interior
// viscosity lambda mu: u - kappa K[u] = 2/(1 + lambda) (u_inf + u_SL)
// (second_kind_solve.hpp, Pozrikidis 1992 ch. 5), deflated, from the guess of the
// earlier evaluations' velocities (guess_history.hpp); in the periodic box with the
// periodic double layer (periodic_double_layer.hpp, PeriodicBox::double_layer:
// Spectral-Ewald sums where the single layer's are, plain ones otherwise), whose mean
// velocity is u_inf's: the suspension's true mean differs from it by a uniform
// translation, which moves no capsule relative to another and no stress.
void CpuFlow::solve_viscosity_ratio(const std::vector<Vec3>& x, double t,
                                    std::vector<Vec3>& u) const {
  const double lambda = setup_.lambda;
  std::vector<Vec3> f(u.size());
  for (size_t i = 0; i < u.size(); ++i)
    f[i] = (2.0 / (1.0 + lambda)) * u[i];
  // The first evaluation starts from u_inf + u_SL, the lambda = 1 velocity.
  std::vector<Vec3> w = history_.empty() ? u : first_guess(x, t);
  SecondKindOptions options;
  options.tolerance = setup_.gmres_tolerance;
  options.deflate = true;
  const PeriodicBox& b = setup_.box;
  const bool spectral = b.method == EwaldMethod::spectral;
  const SecondKindBox box{lattice(t), b.double_layer,
                          spectral ? &b.double_layer_grid : nullptr,
                          spectral ? &b.double_layer_self : nullptr,
                          spectral ? &b.double_layer_self_grid : nullptr};
  const SecondKindResult r =
      solve_second_kind(membrane().topology(), num_capsules(), x, lambda, f,
                        setup_.quadrature, options, w, periodic() ? &box : nullptr);
  if (profile_) {
    profile_->double_layer_setup += r.setup_seconds;
    profile_->double_layer_apply += r.apply_seconds;
  }
  ++stats_.solves;
  stats_.iterations += r.iterations;
  stats_.max_iterations = std::max(stats_.max_iterations, r.iterations);
  stats_.max_residual = std::max(stats_.max_residual, r.residual);
  if (!r.converged) {
    std::ostringstream m;
    m << "the second-kind solve (lambda " << lambda << ") did not converge at t = " << t
      << ": relative residual " << r.residual << " after " << r.iterations
      << " GMRES iterations";
    throw SimulationError(m.str());
  }
  remember(x, t, w);
  u = std::move(w);
}

// gmres.guess extrapolated follows the disturbance u - u_inf: u_inf jumps by the box's
// shear velocity where Lees-Edwards remapping (lees_edwards.hpp) puts a capsule back
// across the sheared faces between two steps, the disturbance does not (a line through
// the jump would miss the next solution by twice the jump). previous keeps the velocity
// itself, as the runs before the option took it.
void CpuFlow::remember(const std::vector<Vec3>& x, double t,
                       const std::vector<Vec3>& u) const {
  if (setup_.gmres_guess == GmresGuess::previous)
    return history_.record(t, u);
  std::vector<Vec3> v = u;
  add_shear_flow(x, setup_.shear_rate, -1, v);
  history_.record(t, v);
}

std::vector<Vec3> CpuFlow::first_guess(const std::vector<Vec3>& x, double t) const {
  std::vector<Vec3> g = history_.guess(t);
  if (setup_.gmres_guess == GmresGuess::extrapolated)
    add_shear_flow(x, setup_.shear_rate, 1, g);
  return g;
}

} // namespace capsim
