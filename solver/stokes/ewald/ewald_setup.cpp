#include "stokes/ewald/ewald_setup.hpp"

#include "stokes/ewald/ewald_reciprocal.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace capsim {

EwaldMethod parse_ewald_method(const std::string& name) {
  return parse_choice("method", name, kEwaldMethods);
}

std::string to_string(EwaldMethod m) {
  return choice_name(m, kEwaldMethods);
}

namespace {

// Patches keep the xi that balances equal per-term costs for all quadrature points:
// balancing for their fewer sources, or for the cheaper reciprocal terms as `direct`
// does, would raise xi and with it the coarse-graining error, which grows like (xi d)^2
// for patches of diameter d.
double automatic_xi(double L, EwaldMethod method, double tolerance, long nodes,
                    long points) {
  switch (method) {
  case EwaldMethod::spectral:
    return spectral_xi(L, tolerance, nodes, points);
  case EwaldMethod::patches:
    return balanced_xi(L, tolerance, nodes, points);
  case EwaldMethod::direct:
    break;
  }
  return balanced_xi(L, tolerance, nodes, points, kRealPairCost);
}

// A given xi far from the automatic one makes one of the sums explode: the real-space
// sum visits ~(r_cut / L)^3 images of every pair, and the reciprocal sum ~(k_cut L /
// 2 pi)^3 wave vectors or grid points. xi = 1e-9 or 100 in a box of a few radii asked
// for tens of gigabytes (or overflowed the grid size); these bounds are far beyond
// any automatic choice and keep memory within reason.
constexpr double kMaxCutBoxes = 4;      // r_cut / L
constexpr double kMaxWaveNumbers = 128; // k_cut L / (2 pi), per direction

void check_given_xi(double L, double xi, const EwaldParameters& p) {
  std::ostringstream m;
  const double waves = p.k_cut * L / (2.0 * kPi);
  if (p.r_cut > kMaxCutBoxes * L)
    m << xi << " is too small for the box side L = " << L << ": the real-space cut-off "
      << p.r_cut << " would be " << p.r_cut / L << " L (at most " << kMaxCutBoxes
      << " L); raise it or use auto";
  else if (waves > kMaxWaveNumbers)
    m << xi << " is too large for the box side L = " << L << ": the reciprocal sum would "
      << "need k_cut L / 2 pi = " << waves << " wave numbers per direction (at most "
      << kMaxWaveNumbers << "); lower it or use auto";
  if (!m.str().empty())
    throw std::invalid_argument(m.str());
}

bool takes_single(Precision p, double tolerance) {
  return resolve_precision(p, tolerance) == Precision::single_precision;
}

} // namespace

// The double layer's self matrices take one grid pass per capsule and the GMRES
// iterations one pass for all, so their split does best at a smaller xi (a coarser grid
// for the passes, more real-space pairs, but only within each capsule): a solve of 27
// capsules of level 3 at phi 0.3 took 0.54, 0.55, 0.56 and 0.58 of its time at 0.5,
// 0.4, 0.33 and 0.65 of the apply's least-cost xi; 8 capsules of level 2, 0.86 at 0.5.
// At phi 0.1 (a larger box, the same grids) 0.35, 0.5 and 0.65 are as fast within the
// machine's drift and 1.0 is 1.2 times slower (27 capsules of level 3, lambda 5).
constexpr double kSelfMatrixXiFactor = 0.5;

PeriodicBox make_periodic_box(double L, const EwaldOptions& request, long nodes,
                              long points, double max_cut_fraction) {
  PeriodicBox box;
  box.L = L;
  box.method = request.method;
  box.patch_level = request.patch_level;
  const double tolerance = request.tolerance;
  double xi = request.xi;
  if (xi <= 0) {
    xi = automatic_xi(L, request.method, tolerance, nodes, points);
    // r_cut = x_cut / xi: a 5 % margin below the limit.
    const double x_cut = choose_ewald_parameters(L, tolerance, 1.0).r_cut;
    xi = std::max(xi, x_cut / (0.95 * max_cut_fraction * L));
  }
  box.ewald = choose_ewald_parameters(L, tolerance, xi);
  box.ewald.single_real = takes_single(request.real_space_precision, tolerance);
  if (request.xi > 0)
    check_given_xi(L, xi, box.ewald);
  const EwaldMethod double_layer_method = request.method == EwaldMethod::spectral
                                              ? EwaldMethod::spectral
                                              : EwaldMethod::direct;
  box.double_layer = choose_ewald_parameters(
      L, tolerance, automatic_xi(L, double_layer_method, tolerance, nodes, points));
  if (request.method == EwaldMethod::spectral) {
    box.double_layer_grid =
        choose_stresslet_spectral_parameters(L, box.double_layer, tolerance);
    box.double_layer_self =
        choose_ewald_parameters(L, tolerance, kSelfMatrixXiFactor * box.double_layer.xi);
    box.double_layer_self_grid =
        choose_stresslet_spectral_parameters(L, box.double_layer_self, tolerance);
    box.grid = choose_spectral_parameters(L, box.ewald, tolerance);
    box.grid.single = takes_single(request.precision, tolerance);
  }
  return box;
}

Precision resolve_precision(Precision p, double tolerance, bool available) {
  if (p != Precision::automatic)
    return p;
  return available && tolerance >= kSinglePrecisionTolerance
             ? Precision::single_precision
             : Precision::double_precision;
}

Precision parse_precision(const std::string& name) {
  if (name == "double")
    return Precision::double_precision;
  if (name == "single")
    return Precision::single_precision;
  if (name == "auto")
    return Precision::automatic;
  throw std::invalid_argument("must be one of {double, single, auto}, got '" + name +
                              "'");
}

std::string to_string(Precision p) {
  switch (p) {
  case Precision::double_precision:
    return "double";
  case Precision::single_precision:
    return "single";
  case Precision::automatic:
    return "auto";
  }
  throw std::logic_error("a precision without a name");
}

ReciprocalSum reciprocal_sum(const PeriodicBox& box, SpectralEwald* spectral) {
  ReciprocalSum r;
  if (box.method == EwaldMethod::spectral)
    r.spectral = spectral;
  else if (box.method == EwaldMethod::patches)
    r.patch_level = box.patch_level;
  return r;
}

} // namespace capsim
