#pragma once
// The time schemes of the node positions dx/dt = u(x, t), u the volume-preserving
// velocity of the flow (Flow::volume_preserving_velocity), each with an embedded error
// estimate for the adaptive step (dynamics/adaptive_step.hpp):
//   heun: explicit 2nd-order Runge-Kutta (paper eq. 3.2), stable for dt ~ Ca h only;
//   imex: the linearly implicit 2nd-order Rosenbrock-W scheme ROS2 (Verwer, Spee, Blom &
//         Hundsdorfer 1999), gamma = 1 + 1/sqrt 2, with W = I - gamma dt J and J the
//         stiff membrane part of the Jacobian (dynamics/stiff_membrane.hpp):
//           W k1 = u(x, t),  W k2 = u(x + dt k1, t + dt) - 2 k1,
//           x <- x + dt (3/2 k1 + 1/2 k2).
//         As a W-method it keeps order 2 for any J; an approximate J costs accuracy
//         constants, not order. Everything not in J (the capsule's far field, the other
//         capsules, the shear) is treated explicitly through u.
//   rkc:  the damped 2nd-order Runge-Kutta-Chebyshev scheme of s stages (Sommeijer,
//         Shampine & Verwer 1998, "RKC: an explicit solver for parabolic PDEs", damping
//         eps = 2/13): explicit, s evaluations a step, stable along the negative real
//         axis up to beta(s) ~ 0.65 s^2 (Heun: 2). The membrane's stiff modes are real
//         and negative (Heun's limit is a real-axis limit), so a step costs s / 2 Heun
//         steps and may be beta(s) / 2 times longer.
#include "common/choice.hpp"
#include "dynamics/flow.hpp"
#include "dynamics/step_error.hpp"
#include "dynamics/stiff_membrane.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace capsim {

enum class TimeScheme { heun, imex, rkc };

// The names of time.scheme, written once: the run key, its parsing and its printing.
inline constexpr Choice<TimeScheme> kTimeSchemes[] = {
    {"heun", TimeScheme::heun}, {"imex", TimeScheme::imex}, {"rkc", TimeScheme::rkc}};

std::string to_string(TimeScheme s);

// One Heun step from time t (paper eq. 3.2, explicit 2nd-order Runge-Kutta) on the
// flow's volume-preserving velocity u: x* = x + dt u(x, t); x <- x + dt/2 (u(x, t) +
// u(x*, t + dt)). Returns the embedded error estimate, the norm n of the node distances
// to the Euler step x*: dt/2 |u1 - u0| (dynamics/step_error.hpp).
double heun_step(const Flow& flow, std::vector<Vec3>& x, double t, double dt,
                 ErrorNorm n = ErrorNorm::max);

// The coefficients of the s-stage RKC scheme (Sommeijer et al. 1998, eqs. 2.2-2.6):
//   Y_0 = x,  Y_1 = Y_0 + mu~_1 dt F_0,
//   Y_j = (1 - mu_j - nu_j) Y_0 + mu_j Y_{j-1} + nu_j Y_{j-2} + mu~_j dt F(Y_{j-1},
//         t + c_{j-1} dt) + gamma~_j dt F_0  (j = 2 .. s),  x <- Y_s,
// with F_0 = F(Y_0, t); index j of each vector (entries 0 and 1 of mu, nu, gamma~
// unused).
struct RkcCoefficients {
  int stages = 0;
  std::vector<double> mu, nu, mu_tilde, gamma_tilde, c;
  double beta = 0; // the stability boundary: |R(z)| <= 1 for z in [-beta, 0]
};
RkcCoefficients rkc_coefficients(int stages); // stages >= 2

// How much longer a step than Heun's the scheme's real-axis stability allows: beta(s)
// / 2 for rkc, 1 for heun and imex (whose automatic step is only its first).
double stability_ratio(TimeScheme scheme, int stages);

// The velocity the schemes step: u(x, t) of the nodes x into u.
using Velocity =
    std::function<void(const std::vector<Vec3>&, double, std::vector<Vec3>&)>;

// One RKC step of x from t by dt; u0 receives F_0 = u(x, t).
void rkc_step(const RkcCoefficients& k, const Velocity& velocity, std::vector<Vec3>& x,
              double t, double dt, std::vector<Vec3>& u0);

class Stepper {
public:
  virtual ~Stepper() = default;
  // Advances x from t by dt; returns the embedded estimate of the local error, the
  // norm (dynamics/step_error.hpp) of the node distances between the scheme's step and
  // its first-order companion's.
  virtual double step(std::vector<Vec3>& x, double t, double dt) = 0;
};

class HeunStepper : public Stepper {
public:
  explicit HeunStepper(const Flow& flow, ErrorNorm norm = ErrorNorm::max)
      : flow_(flow), norm_(norm) {}
  double step(std::vector<Vec3>& x, double t, double dt) override {
    return heun_step(flow_, x, t, dt, norm_);
  }

private:
  const Flow& flow_;
  ErrorNorm norm_;
};

class ImexStepper : public Stepper {
public:
  explicit ImexStepper(const Flow& flow, ErrorNorm norm = ErrorNorm::max);
  // The first-order companion is x + dt k1, so the node errors are dt/2 (k1 + k2).
  double step(std::vector<Vec3>& x, double t, double dt) override;

private:
  const Flow& flow_;
  StiffMembrane stiff_;
  ErrorNorm norm_;
};

class RkcStepper : public Stepper {
public:
  RkcStepper(const Flow& flow, int stages, ErrorNorm norm = ErrorNorm::max);
  // The first-order companion is the Euler step x + dt F_0.
  double step(std::vector<Vec3>& x, double t, double dt) override;

private:
  const Flow& flow_;
  RkcCoefficients k_;
  ErrorNorm norm_;
};

// The automatic step: dt = safety * Ca * h, h the mean edge length of the undeformed
// mesh. The membrane's fastest relaxation mode on scale h has rate ~ Gs/(mu h) = 1/(Ca
// h), so an explicit scheme needs dt = O(Ca h) (Heun is stable up to safety 1.38-1.58 at
// levels 2-4, docs/time_stepping.md). A bending modulus eb = kb / (Gs a^2) adds modes of
// rate ~ Gs eb / (mu h^3): alone they allow dt up to about 0.2 Ca h^3 / eb (measured on a
// relaxing capsule at levels 2 and 3), so the step becomes safety * Ca * h / (1 + 4 eb /
// h^2), which tends to 0.125 Ca h^3 / eb at safety 0.5.
double automatic_time_step(double ca, double mean_edge, double safety,
                           double bending = 0);

// stages: of rkc (ignored by the others).
std::unique_ptr<Stepper> make_stepper(TimeScheme scheme, const Flow& flow,
                                      ErrorNorm norm = ErrorNorm::max, int stages = 4);

} // namespace capsim
