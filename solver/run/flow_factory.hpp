#pragma once
// The one place that turns a backend name into a flow: checks that the backend can run
// here and can evaluate the set-up, then builds it.
#include "dynamics/flow.hpp"

#include <memory>

namespace capsim {

// What `backend` can evaluate.
FlowCapabilities capabilities_of(Backend backend);

// Here, where the run keys are known (not in dynamics/): "" when `caps` cover `setup`,
// else one line naming the run key to change and why
// (`backend` names the backend in the message).
std::string unsupported_by(const FlowSetup& setup, const FlowCapabilities& caps,
                           Backend backend);

// Throws ConfigError, one line naming the key to change, when `backend` cannot run here
// or lacks a capability the set-up needs.
void check_flow_supported(Backend backend, const FlowSetup& setup);

// check_flow_supported, then the flow on `backend`.
std::unique_ptr<Flow> make_flow(Backend backend, const FlowSetup& setup);

} // namespace capsim
