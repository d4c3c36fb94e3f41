#pragma once
// Whether the CUDA backend can run on this machine. Plain C++: answered by
// device_query.cpp when the backend is compiled, by cuda_unavailable.cpp otherwise.
#include <string>

namespace capsim {

bool cuda_backend_compiled();

// Empty when a CUDA device can run the backend; otherwise one line saying why not.
std::string cuda_unavailable_reason();

// Name, compute capability and memory of the device the backend uses (device 0).
std::string cuda_device_description();

} // namespace capsim
