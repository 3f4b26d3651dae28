// The foundation's main job: the colon settling under gravity and its mesentery.
#pragma once

#include <cstdint>
#include <string>

#include "core/world.h"

namespace colosim {

struct SettleSummary {
  int n_control_points = 0;
  double length_m = 0;
  double duration_s = 0;
  double dt_s = 0;
  long steps = 0;
  double energy_start_J = 0;       ///< total energy at t = 0 [J]
  double energy_end_J = 0;         ///< total energy at the end [J]
  double kinetic_end_J = 0;        ///< kinetic energy at the end [J]
  double max_displacement_m = 0;   ///< largest |q - q0| over control points at the end [m]
  std::string max_displacement_region;
  double max_speed_end_m_per_s = 0;
  double us_per_step_median = 0;   ///< median over blocks of 100 steps [us]
  bool finite = true;              ///< no NaN or infinity anywhere
  uint64_t state_hash = 0;         ///< hashColonState at the end: equal hashes mean bit-identical runs
};

/// Simulates the world's colon from rest for duration_s at dt_s (the settling of a start
/// state, trainer/start_state.h, the scope out) and summarises.
SettleSummary settleColon(const WorldModel& model, double duration_s, double dt_s);

}  // namespace colosim
