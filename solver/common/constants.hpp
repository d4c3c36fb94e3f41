#pragma once
// Mathematical constants shared by every layer (host and device code).

namespace capsim {

constexpr double kPi = 3.14159265358979323846;

} // namespace capsim
