#include "stokes/ewald_setup.hpp"

#include "stokes/ewald_reciprocal.hpp"

#include <algorithm>
#include <stdexcept>

namespace capsim {

EwaldMethod parse_ewald_method(const std::string& name) {
  if (name == "spectral")
    return EwaldMethod::spectral;
  if (name == "direct")
    return EwaldMethod::direct;
  if (name == "patches")
    return EwaldMethod::patches;
  throw std::invalid_argument("method must be one of {spectral, direct, patches}, got '" +
                              name + "'");
}

std::string to_string(EwaldMethod m) {
  switch (m) {
  case EwaldMethod::spectral:
    return "spectral";
  case EwaldMethod::direct:
    return "direct";
  case EwaldMethod::patches:
    return "patches";
  }
  return "";
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

} // namespace

PeriodicBox make_periodic_box(double L, const EwaldRequest& request, long nodes,
                              long points) {
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
    xi = std::max(xi, x_cut / (0.95 * request.max_cut_fraction * L));
  }
  box.ewald = choose_ewald_parameters(L, tolerance, xi);
  if (request.method == EwaldMethod::spectral)
    box.grid = choose_spectral_parameters(L, box.ewald, tolerance);
  return box;
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
