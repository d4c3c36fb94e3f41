#pragma once
// The one number the step controller (dynamics/adaptive_step.hpp) compares with
// time.tolerance, from a step's node errors e_i: the distance, in capsule radii, between
// the scheme's step and its first-order companion's at node i.
//   max: the largest |e_i| over all nodes. One node anywhere sets the step of all: in a
//        suspension of M capsules the step follows the worst node of the worst moment.
//   rms: the root mean square of |e_i| over each capsule's nodes, the largest over the
//        capsules (the RMS norm of stiff ODE codes with an absolute tolerance, Hairer &
//        Wanner, Solving ODEs II, IV.8, taken per capsule): a local feature of a capsule
//        (a wrinkle, a close neighbour) counts in proportion to its extent, and each
//        capsule is still held to the tolerance on its own.
#include "common/choice.hpp"
#include "common/vec3.hpp"

#include <string>
#include <vector>

namespace capsim {

enum class ErrorNorm { max, rms };

// The names of time.error_norm, written once: the run key, its parsing and its printing.
inline constexpr Choice<ErrorNorm> kErrorNorms[] = {{"max", ErrorNorm::max},
                                                    {"rms", ErrorNorm::rms}};

ErrorNorm parse_error_norm(const std::string& name); // throws std::invalid_argument
std::string to_string(ErrorNorm n);

// The norm of the node errors e (capsule after capsule, num_capsules equal blocks).
double step_error(const std::vector<Vec3>& e, int num_capsules, ErrorNorm n);

} // namespace capsim
