#include "dynamics/step_error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace capsim {

ErrorNorm parse_error_norm(const std::string& name) {
  return parse_choice("time.error_norm", name, kErrorNorms);
}

std::string to_string(ErrorNorm n) {
  return choice_name(n, kErrorNorms);
}

double step_error(const std::vector<Vec3>& e, int num_capsules, ErrorNorm n) {
  const size_t per_capsule = e.size() / size_t(std::max(num_capsules, 1));
  if (per_capsule == 0)
    return 0;
  double err = 0;
  for (size_t begin = 0; begin < e.size(); begin += per_capsule) {
    double capsule = 0;
    for (size_t i = begin; i < begin + per_capsule; ++i) {
      const double ei = norm(e[i]);
      if (std::isnan(ei))
        return ei; // the controller rejects a NaN; std::max would drop it
      capsule = n == ErrorNorm::max ? std::max(capsule, ei) : capsule + ei * ei;
    }
    if (n == ErrorNorm::rms)
      capsule = std::sqrt(capsule / double(per_capsule));
    err = std::max(err, capsule);
  }
  return err;
}

} // namespace capsim
