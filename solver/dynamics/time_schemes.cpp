#include "dynamics/time_schemes.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace capsim {

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

RkcCoefficients rkc_coefficients(int s) {
  if (s < 2)
    throw std::invalid_argument("rkc: at least 2 stages");
  // Chebyshev polynomials T_j and their first two derivatives at w0 (eq. 2.4).
  const double eps = 2.0 / 13.0, w0 = 1.0 + eps / (s * s);
  std::vector<double> T(s + 1), dT(s + 1), ddT(s + 1);
  T[0] = 1, T[1] = w0, dT[0] = 0, dT[1] = 1, ddT[0] = 0, ddT[1] = 0;
  for (int j = 2; j <= s; ++j) {
    T[j] = 2 * w0 * T[j - 1] - T[j - 2];
    dT[j] = 2 * T[j - 1] + 2 * w0 * dT[j - 1] - dT[j - 2];
    ddT[j] = 4 * dT[j - 1] + 2 * w0 * ddT[j - 1] - ddT[j - 2];
  }
  const double w1 = dT[s] / ddT[s];
  std::vector<double> b(s + 1);
  for (int j = 2; j <= s; ++j)
    b[j] = ddT[j] / (dT[j] * dT[j]);
  b[0] = b[1] = b[2];
  RkcCoefficients k;
  k.stages = s;
  k.mu.assign(s + 1, 0), k.nu.assign(s + 1, 0), k.mu_tilde.assign(s + 1, 0);
  k.gamma_tilde.assign(s + 1, 0), k.c.assign(s + 1, 0);
  k.mu_tilde[1] = b[1] * w1;
  k.c[1] = k.mu_tilde[1];
  for (int j = 2; j <= s; ++j) {
    const double a_prev = 1 - b[j - 1] * T[j - 1];
    k.mu[j] = 2 * w0 * b[j] / b[j - 1];
    k.nu[j] = -b[j] / b[j - 2];
    k.mu_tilde[j] = 2 * w1 * b[j] / b[j - 1];
    k.gamma_tilde[j] = -a_prev * k.mu_tilde[j];
    k.c[j] =
        k.mu[j] * k.c[j - 1] + k.nu[j] * k.c[j - 2] + k.mu_tilde[j] + k.gamma_tilde[j];
  }
  k.beta = (w0 + 1) * ddT[s] / dT[s]; // eq. 2.7
  return k;
}

double stability_ratio(TimeScheme scheme, int stages) {
  return scheme == TimeScheme::rkc ? rkc_coefficients(stages).beta / 2 : 1.0;
}

void rkc_step(const RkcCoefficients& k, const Velocity& velocity, std::vector<Vec3>& x,
              double t, double dt, std::vector<Vec3>& u0) {
  const size_t n = x.size();
  velocity(x, t, u0);
  std::vector<Vec3> previous(x), current(n), u;
  for (size_t i = 0; i < n; ++i)
    current[i] = x[i] + (k.mu_tilde[1] * dt) * u0[i];
  for (int j = 2; j <= k.stages; ++j) {
    velocity(current, t + k.c[j - 1] * dt, u);
    const double keep = 1 - k.mu[j] - k.nu[j];
    for (size_t i = 0; i < n; ++i) {
      const Vec3 next = keep * x[i] + k.mu[j] * current[i] + k.nu[j] * previous[i] +
                        (k.mu_tilde[j] * dt) * u[i] + (k.gamma_tilde[j] * dt) * u0[i];
      previous[i] = current[i];
      current[i] = next;
    }
  }
  x = current;
}

RkcStepper::RkcStepper(const Flow& flow, int stages, ErrorNorm norm)
    : flow_(flow), k_(rkc_coefficients(stages)), norm_(norm) {}

double RkcStepper::step(std::vector<Vec3>& x, double t, double dt) {
  std::vector<Vec3> start(x), u0;
  rkc_step(
      k_,
      [&](const std::vector<Vec3>& y, double time, std::vector<Vec3>& u) {
        flow_.volume_preserving_velocity(y, time, u);
      },
      x, t, dt, u0);
  std::vector<Vec3>& error = start; // the distance to the Euler step
  for (size_t i = 0; i < x.size(); ++i)
    error[i] = x[i] - (start[i] + dt * u0[i]);
  return step_error(error, flow_.num_capsules(), norm_);
}

double automatic_time_step(double ca, double mean_edge, double safety, double bending) {
  return safety * ca * mean_edge / (1 + 4 * bending / (mean_edge * mean_edge));
}

std::unique_ptr<Stepper> make_stepper(TimeScheme scheme, const Flow& flow, ErrorNorm norm,
                                      int stages) {
  if (scheme == TimeScheme::imex)
    return std::make_unique<ImexStepper>(flow, norm);
  if (scheme == TimeScheme::rkc)
    return std::make_unique<RkcStepper>(flow, stages, norm);
  return std::make_unique<HeunStepper>(flow, norm);
}

} // namespace capsim
