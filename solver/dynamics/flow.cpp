#include "dynamics/flow.hpp"

#include "common/choice.hpp"
#include "dynamics/time_stepping.hpp"

#include <algorithm>
#include <omp.h>
#include <stdexcept>

namespace capsim {

constexpr Choice<Backend> kBackends[] = {{"cpu", Backend::cpu}, {"cuda", Backend::cuda}};

Backend parse_backend(const std::string& name) {
  return parse_choice("backend", name, kBackends);
}

std::string to_string(Backend b) {
  return choice_name(b, kBackends);
}

namespace {

// Heun's embedded error estimate from its two stages: the norm n of the node errors
// dt/2 (u1_i - u0_i) of num_capsules capsules.
double heun_error(const std::vector<Vec3>& u0, const std::vector<Vec3>& u1, double dt,
                  int num_capsules, ErrorNorm n) {
  std::vector<Vec3> e(u0.size());
  for (size_t i = 0; i < u0.size(); ++i)
    e[i] = (0.5 * dt) * (u1[i] - u0[i]);
  return step_error(e, num_capsules, n);
}

} // namespace

void Flow::velocity(const std::vector<Vec3>& x, double t, std::vector<Vec3>& u) const {
  const double t0 = omp_get_wtime();
  evaluate_velocity(x, t, u);
  if (profile_) {
    ++profile_->evaluations;
    profile_->velocity += omp_get_wtime() - t0;
  }
}

void Flow::volume_preserving_velocity(const std::vector<Vec3>& x, double t,
                                      std::vector<Vec3>& u) const {
  velocity(x, t, u);
  const double t1 = omp_get_wtime();
  remove_volume_rate(membrane().topology(), num_capsules(), x, u);
  if (profile_)
    profile_->volume_rate += omp_get_wtime() - t1;
}

double Flow::heun_step(std::vector<Vec3>& x, double t, double dt, ErrorNorm n) const {
  std::vector<Vec3> u0, u1, xs(x.size());
  volume_preserving_velocity(x, t, u0);
  for (size_t i = 0; i < x.size(); ++i)
    xs[i] = x[i] + dt * u0[i];
  volume_preserving_velocity(xs, t + dt, u1);
  for (size_t i = 0; i < x.size(); ++i)
    x[i] += (0.5 * dt) * (u0[i] + u1[i]);
  return heun_error(u0, u1, dt, num_capsules(), n);
}

std::vector<double> Flow::energy_gradient(const std::vector<Vec3>& x,
                                          std::vector<Vec3>& grad) const {
  const int nn = membrane().topology().num_nodes;
  grad.resize(x.size());
  std::vector<double> energy(num_capsules());
  std::vector<Vec3> g;
  for (int c = 0; c < num_capsules(); ++c) {
    energy[c] = membrane().energy_gradient(&x[c * nn], g);
    std::copy(g.begin(), g.end(), grad.begin() + c * nn);
  }
  return energy;
}

std::vector<int> Flow::add_repulsion(const std::vector<Vec3>& x, double t,
                                     std::vector<Vec3>& grad) const {
  std::vector<int> count(num_capsules(), 0);
  if (setup_.repulsion.on() && periodic())
    add_repulsion_gradient(lattice(t), membrane().topology().num_nodes, x,
                           setup_.repulsion, grad, &count);
  return count;
}

} // namespace capsim
