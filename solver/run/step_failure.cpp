#include "run/step_failure.hpp"

#include "membrane/compression.hpp"

#include <iomanip>
#include <sstream>

namespace capsim {

namespace {

const char* const kStepAdvice =
    ". The time step is probably too large for this Ca and mesh: start again with a "
    "smaller dt or dt_safety (the output folder keeps the last good checkpoint and time "
    "series)";

std::string tension_text(double t) {
  std::ostringstream s;
  s << std::setprecision(2) << t << " Gs";
  return s.str();
}

// What an inverted triangle says of its cause: with compressed elements next to it the
// membrane buckled (docs/suspensions.md: halving dt moved no such fold); otherwise the
// step was too large.
std::string inversion_cause(const Membrane& membrane, const Vec3* xc, int triangle) {
  const std::vector<ElementTensions> t = membrane.neo_hookean_element_tensions(xc);
  const Compression all = compression(t);
  const Compression near = compression_near(membrane.topology(), t, triangle);
  if (all.elements == 0)
    return kStepAdvice;
  std::ostringstream s;
  // A relaxed membrane carries no compression: the paper's energy's T2 then says where
  // it wrinkles and how far the elements there are squeezed, not a tension it carries.
  s << "; " << all.elements << " of its " << all.of << " elements are in compression"
    << (membrane.wrinkling() ? " under the paper's energy, which the relaxed membrane "
                               "does not carry"
                             : "")
    << " (T2 < " << kCompressedTension << " Gs)";
  if (near.elements == 0)
    return s.str() + ", down to T2 = " + tension_text(all.min_tension) +
           ", none next to the inverted one" + kStepAdvice;
  s << ", down to T2 = " << tension_text(near.min_tension)
    << " next to the inverted one: the membrane buckles under compressive tension, "
       "which nothing resists at the element scale without bending stiffness, and "
       "which a smaller dt did not cure in the measured cases ("
    << (membrane.wrinkling() ? "membrane.wrinkling is on, so the membrane wrinkles "
                               "there; membrane.bending regularises the fold"
                             : "membrane.wrinkling or membrane.bending regularise it")
    << "; docs/suspensions.md). The output folder keeps the last good checkpoint and "
       "time series";
  return s.str();
}

} // namespace

void check_state(const Membrane& membrane, int num_capsules, const std::vector<Vec3>& x,
                 double time, double max_extent) {
  const Topology& topo = membrane.topology();
  const StateFault f = find_fault(topo, num_capsules, x, max_extent);
  if (f.capsule < 0)
    return;
  std::ostringstream s;
  s << "numerical failure at gammadot*t = " << time << " in capsule " << f.capsule << ": "
    << f.what
    << (f.triangle >= 0
            ? inversion_cause(membrane, &x[f.capsule * topo.num_nodes], f.triangle)
            : kStepAdvice);
  throw SimulationError(s.str());
}

void check_contact(const Topology& topo, int num_capsules, const ShearedLattice& lattice,
                   const std::vector<Vec3>& x, double stop_distance, double time) {
  const ClosestApproach c =
      closest_approach(topo, num_capsules, lattice, x, stop_distance);
  if (!(c.distance < stop_distance))
    return;
  const std::string who =
      c.capsule_a == c.capsule_b
          ? "capsule " + std::to_string(c.capsule_a) + " and its periodic image touch"
          : "capsules " + std::to_string(c.capsule_a) + " and " +
                std::to_string(c.capsule_b) + " touch";
  throw SimulationError(who + " at gammadot*t = " + std::to_string(time) +
                            " (node distance " + std::to_string(c.distance) +
                            " < suspension.stop_distance): the near-contact "
                            "flow is under-resolved; start again with a smaller dt or a "
                            "finer mesh (the output "
                            "folder keeps the last good checkpoint and time series)",
                        "contact");
}

} // namespace capsim
