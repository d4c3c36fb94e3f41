#include "dynamics/cpu_flow.hpp"

#include "dynamics/state_checks.hpp"

#include <omp.h>

namespace capsim {

CpuFlow::CpuFlow(const FlowSetup& setup) : Flow(setup) {
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
  for (size_t i = 0; i < x.size(); ++i)
    u[i].x += setup_.shear_rate * x[i].y;
  require_finite(u, topo.num_nodes, "velocity", t);
}

} // namespace capsim
