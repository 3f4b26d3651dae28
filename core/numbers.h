// Mathematical constants shared across colosim (C++17 has no std::numbers).
#pragma once

namespace colosim {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace colosim
