#include "dynamics/time_schemes.hpp"

#include "common/choice.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace capsim {

constexpr Choice<TimeScheme> kTimeSchemes[] = {{"heun", TimeScheme::heun},
                                               {"imex", TimeScheme::imex}};

TimeScheme parse_time_scheme(const std::string& name) {
  return parse_choice("time.scheme", name, kTimeSchemes);
}

std::string to_string(TimeScheme s) {
  return choice_name(s, kTimeSchemes);
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

double heun_step(const Flow& flow, std::vector<Vec3>& x, double t, double dt,
                 ErrorNorm n) {
  std::vector<Vec3> u0, u1, xs(x.size());
  flow.volume_preserving_velocity(x, t, u0);
  for (size_t i = 0; i < x.size(); ++i)
    xs[i] = x[i] + dt * u0[i];
  flow.volume_preserving_velocity(xs, t + dt, u1);
  for (size_t i = 0; i < x.size(); ++i)
    x[i] += (0.5 * dt) * (u0[i] + u1[i]);
  return heun_error(u0, u1, dt, flow.num_capsules(), n);
}

ImexStepper::ImexStepper(const Flow& flow, ErrorNorm norm)
    : flow_(flow), stiff_(flow.membrane(), flow.num_capsules(), flow.setup().quadrature),
      norm_(norm) {}

double ImexStepper::step(std::vector<Vec3>& x, double t, double dt) {
  const double gamma = 1.0 + 1.0 / std::sqrt(2.0);
  stiff_.prepare(x, gamma * dt);
  std::vector<Vec3> k1, k2, xs(x.size());
  flow_.volume_preserving_velocity(x, t, k1);
  stiff_.solve(k1);
  for (size_t i = 0; i < x.size(); ++i)
    xs[i] = x[i] + dt * k1[i];
  flow_.volume_preserving_velocity(xs, t + dt, k2);
  for (size_t i = 0; i < x.size(); ++i)
    k2[i] -= 2.0 * k1[i];
  stiff_.solve(k2);
  std::vector<Vec3>& error = xs; // x + dt k1 is no longer needed
  for (size_t i = 0; i < x.size(); ++i) {
    x[i] += dt * (1.5 * k1[i] + 0.5 * k2[i]);
    error[i] = (0.5 * dt) * (k1[i] + k2[i]);
  }
  return step_error(error, flow_.num_capsules(), norm_);
}

double automatic_time_step(double ca, double mean_edge, double safety, double bending) {
  return safety * ca * mean_edge / (1 + 4 * bending / (mean_edge * mean_edge));
}

std::unique_ptr<Stepper> make_stepper(TimeScheme scheme, const Flow& flow,
                                      ErrorNorm norm) {
  if (scheme == TimeScheme::imex)
    return std::make_unique<ImexStepper>(flow, norm);
  return std::make_unique<HeunStepper>(flow, norm);
}

} // namespace capsim
