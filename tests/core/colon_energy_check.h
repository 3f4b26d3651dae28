// Shared by the colon step's tests and its extensions' tests: with damping, the colon's
// mechanical energy never increases, step after step; and a chain held by end loads.
#pragma once

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/colon_model.h"
#include "core/colon_state.h"
#include "core/colon_step.h"
#include "tests/random_vec3.h"

namespace colosim::test {

/// From rest plus a seeded random kick of the control points' velocities (normal, standard
/// deviation kick_m_per_s [m/s] per component), steps the colon `steps` times at dt_s [s]
/// and fails at the first step whose total energy exceeds the previous one's by more than
/// 1e-12 J.
inline void expectEnergyNeverIncreases(const ColonModel& m, int steps, double dt_s, unsigned seed = 11,
                                       double kick_m_per_s = 0.2) {
  ColonState s = makeColonState(m);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, kick_m_per_s);
  for (int i = 0; i < m.n; ++i) s.v.col(i) = randomVec3(n01, rng);
  double e_prev = colonEnergy(m, s).total();
  for (int k = 0; k < steps; ++k) {
    stepColon(m, s, dt_s);
    const double e = colonEnergy(m, s).total();
    ASSERT_LE(e, e_prev + 1e-12) << "step " << k;
    e_prev = e;
  }
}

/// Steps a straight chain along x `steps` times at dt_s [s] with equal and opposite loads
/// on its two ends, `pull_N` [N] outwards (negative: pushing the ends together).
inline void stepUnderEndLoads(const ColonModel& m, ColonState& s, double pull_N, int steps, double dt_s) {
  for (int k = 0; k < steps; ++k) {
    s.loads.clear();
    SplineLoad a, b;
    a.segment = 0, a.p = 0.0, a.force_N = Vec3(-pull_N, 0, 0);
    b.segment = m.n - 2, b.p = 1.0, b.force_N = Vec3(pull_N, 0, 0);
    s.loads.push_back(a);
    s.loads.push_back(b);
    stepColon(m, s, dt_s);
  }
}

/// Steps the colon `steps` times at dt_s [s] with one load on segment 30 (p 0.25): 200 N/m
/// stiff, its force swinging sideways as 0.5 sin(k / 100) N and 0.2 N up. The scripted
/// run the colon's bit-identity tests repeat.
inline void stepUnderASwingingLoad(const ColonModel& m, ColonState& s, int steps, double dt_s) {
  for (int k = 0; k < steps; ++k) {
    s.loads.clear();
    SplineLoad l;
    l.segment = 30;
    l.p = 0.25;
    l.force_N = Vec3(0.5 * std::sin(k * 1e-2), 0, 0.2);
    l.stiffness_N_per_m = 200 * Mat3::Identity();
    s.loads.push_back(l);
    stepColon(m, s, dt_s);
  }
}

}  // namespace colosim::test
