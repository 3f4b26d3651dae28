// A seeded generator of synthetic tension tests: a displacement-controlled bench with a
// hidden effect (or none), for the identification tests and the shipped example data.
// Everything a real bench gives is drawn from physiological ranges
// (../shared/reference/parameters.md): the protocol (ramps at different rates, holds,
// unloading into slack, repeated cycles of varied amplitude), a rounded actuator, a
// slightly irregular time base, a sensor offset, white and slightly coloured noise.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/extended_tension_law.h"
#include "identify/tension/tension_test.h"

namespace colosim {

/// One piece of the commanded elongation: a ramp to target_m at speed_m_per_s, or a hold
/// (speed 0) of duration_s.
struct ProtocolStep {
  double target_m = 0;
  double speed_m_per_s = 0;
  double duration_s = 0;
};

struct SyntheticSpec {
  ExtendedLawParams truth;            ///< the hidden law (its effects are the answer)
  double sample_length_m = 0.18;
  std::vector<ProtocolStep> protocol;
  double actuator_tau_s = 0.2;        ///< first-order lag of the actuator: rounded corners [s]
  double nominal_dt_s = 0.25;         ///< sampling interval [s]
  double jitter = 0.05;               ///< relative jitter of the sampling interval [-]
  double offset_N = 0;                ///< sensor offset [N]
  double white_sd_N = 0.03;           ///< white noise [N]
  double coloured_sd_N = 0.01;        ///< stationary sd of the AR(1) noise [N]
  double coloured_phi = 0.9;          ///< AR(1) coefficient per sample [-]
  /// A force outside every candidate effect, for tests of `unexplained`: dry friction in
  /// the grips, +-friction_N with the sign of the elongation rate while the sample is taut [N].
  double foreign_friction_N = 0;
  uint64_t seed = 0;
};

/// Options of the random draw.
struct SyntheticDraw {
  std::vector<std::string> effects;   ///< hidden effects (empty: the Voigt law)
  double nominal_dt_s = 0.25;         ///< sampling interval [s]
  int cycles = 11;                    ///< loading cycles
  double max_elongation_m = 0;        ///< 0: drawn in [0.09, 0.12] m
  double max_force_N = 0;             ///< 0: drawn in [8, 13] N
  double sample_length_m = 0;         ///< 0: drawn in [0.16, 0.20] m
};

/// Draws a spec (protocol, law parameters, noise) from physiological ranges.
SyntheticSpec drawSyntheticSpec(uint64_t seed, const SyntheticDraw& draw);

/// A draw uniform in [a, b) (the synthetic generators' one way of drawing).
double uniformDraw(std::mt19937_64& rng, double a, double b);

/// Runs the bench: the true law on a 5 ms grid through evaluate()/advance(), sampled at
/// the irregular times, plus offset and noise, rounded as the file stores it.
TensionTest generateTensionTest(const SyntheticSpec& spec);

/// The shipped example (assets/measurements/): two 180 mm samples stretched to 0.12 m with
/// forces up to about 11 N, Fung-stiffening and relaxing, like the paper's Figure 8.
/// sample is 1 or 2. The files are generateTensionTest(shippedSampleSpec(i)).
SyntheticSpec shippedSampleSpec(int sample);

/// Total duration of a protocol [s] (without the final settling).
double protocolDuration(const SyntheticSpec& spec);

}  // namespace colosim
