#include "dynamics/flow.hpp"

#include "dynamics/normal_motion.hpp"
#include "dynamics/volume_constraint.hpp"

#include <algorithm>
#include <omp.h>
#include <stdexcept>

namespace capsim {

Backend parse_backend(const std::string& name) {
  return parse_choice("backend", name, kBackends);
}

std::string to_string(Backend b) {
  return choice_name(b, kBackends);
}

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
  if (membrane().law() == MembraneLaw::drop)
    keep_normal_motion(membrane().topology(), num_capsules(), x, u);
  remove_volume_rate(membrane().topology(), num_capsules(), x, u);
  if (profile_)
    profile_->volume_rate += omp_get_wtime() - t1;
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
