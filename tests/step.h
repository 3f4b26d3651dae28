// The real time step the tests run the simulation at.
#pragma once

namespace colosim {

inline constexpr double kDt = 1e-3;  // [s]

}  // namespace colosim
