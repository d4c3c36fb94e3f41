#pragma once
// The error that ends a run in the middle.
#include <stdexcept>
#include <string>

namespace capsim {

// A run that cannot go on: a numerical failure (kind "numerical": NaN, blow-up, broken
// mesh) or two capsules in contact (kind "contact"). The run stops, the last good
// checkpoint stays, and summary.json records the kind as how the run ended.
struct SimulationError : std::runtime_error {
  explicit SimulationError(const std::string& what, std::string kind = "numerical")
      : std::runtime_error(what), kind(std::move(kind)) {}
  std::string kind;
};

} // namespace capsim
