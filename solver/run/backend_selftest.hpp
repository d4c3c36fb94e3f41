#pragma once
// `capsim selftest --backend B`: evaluates the same small cases on backend B and on the
// CPU backend and prints their differences: the membrane traction, the free-space and the
// periodic (Spectral Ewald) velocity, and a few time steps of each. For users with a GPU
// to check the CUDA backend; with B = cpu it compares the CPU path with itself.
#include "dynamics/flow.hpp"

#include <ostream>

namespace capsim {

// Throws ConfigError when B cannot run here (no GPU, or no CUDA backend compiled).
// Returns true when every difference is within its stated limit.
bool run_backend_selftest(Backend backend, std::ostream& out);

} // namespace capsim
