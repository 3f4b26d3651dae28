// Synthetic insertion recordings: the simulator with a hidden extension switched on, plus
// sensor noise and offsets (tests and assets/measurements/; docs/organ-identification.md).
#pragma once

#include <cstdint>
#include <string>

#include "identify/insertion/replay.h"

namespace colosim {

struct SyntheticInsertionSpec {
  /// The bench's scenario: the attached-rectum free_insertion, on which the hidden-effect
  /// tests and the shipped recording were validated (free_insertion itself now has a
  /// pelvic rectum).
  std::string scenario = "free_insertion_attached_rectum";
  double duration_s = 4.0;
  double sample_hz = 100.0;
  std::string effect;              ///< hidden effect ("" for none)
  double value = 0;                ///< its magnitude
  // The protocol: push at push_speed, a short hold, pull back pull_back_m, push again; or,
  // with cycles > 0, that many insert / withdraw cycles of cycle_amplitude_m from the start
  // depth (insertion start + A (1 - cos(2 pi cycles t / T)) / 2: the colon is stretched,
  // relieved and stretched again; the cyclic_softening case of the tests).
  double start_insertion_m = 0.12;  ///< the scope starts threaded to this depth [m]
  double push_speed_m_per_s = 0.05;
  double pull_back_m = 0.03;
  int cycles = 0;                   ///< insert / withdraw cycles (0: push, hold, pull, push)
  double cycle_amplitude_m = 0.08;  ///< depth pushed and withdrawn in each cycle [m]
  // Or, with holds > 0 (and cycles 0): that many push-and-hold stages of equal duration,
  // each a quick push of hold_step_m over the first hold_ramp_fraction of the stage, then
  // the depth held (a staircase: stress relaxation shows as the force decaying in the holds).
  int holds = 0;
  double hold_step_m = 0.05;        ///< depth pushed at the start of each stage [m]
  double hold_ramp_fraction = 0.2;  ///< part of each stage spent pushing [-]
  // Or, with two_rate (cycles 0, holds 0): from start_insertion_m a slow push of
  // slow_push_m over the first 30 % of the time, a hold of 15 %, a quick push of
  // fast_push_m over 10 %, a hold of 20 %, a withdrawal of pull_back_m over the last 25 %;
  // the rotation wiggles at wiggle_hz and the left-right knob steers (a protocol the unit
  // tests do not use: the organ trials', tools/organ_trials).
  bool two_rate = false;
  double slow_push_m = 0.04, fast_push_m = 0.04;  ///< [m]
  double wiggle_hz = 1.5;                         ///< rotation frequency [Hz]
  double knob_leftright_rad = 0.0;
  double rotation_amplitude_rad = 0.3;
  double knob_updown_rad = 0.3;
  // Sensors.
  double force_noise_N = 0.04, force_offset_N = 0.1;
  double torque_noise_Nm = 0.002, torque_offset_Nm = 0.005;
  double tip_noise_m = 0.001;
  bool with_tip = true;
  uint64_t seed = 1;
};

/// Draws a spec with seeded std::mt19937_64: the effect (one of organEffectNames(), or none
/// when `effect_index` < 0), its magnitude from a physiological range, the protocol and the
/// noise. cycles > 0 selects the cyclic protocol (its amplitude and start depth drawn after
/// everything else, so the other draws of a seed do not depend on it); holds > 0 (cycles 0)
/// the push-and-hold staircase (its step and start depth drawn likewise, after everything else).
SyntheticInsertionSpec drawSyntheticInsertion(uint64_t seed, int effect_index, double duration_s, int cycles = 0,
                                              int holds = 0);
/// The two-rate protocol (SyntheticInsertionSpec::two_rate), drawn after the draws of
/// drawSyntheticInsertion for the same seed: start 40-50 cm, slow push 3-5 cm, quick push
/// 3-5 cm, withdrawal 2-4 cm, rotation wiggle 0.1-0.3 rad at 1-2 Hz, left-right knob
/// -0.3..0.3 rad.
SyntheticInsertionSpec drawTwoRateInsertion(uint64_t seed, int effect_index, double duration_s);

/// The range the magnitude of an effect is drawn from in tests.
std::pair<double, double> syntheticRange(const std::string& effect);

/// Runs the simulator (resolution of `setup`) with the hidden effect and writes the noisy
/// recording's rows; metadata says SYNTHETIC and what was hidden.
InsertionRecording makeSyntheticInsertion(const ReplaySetup& setup, const SyntheticInsertionSpec& spec);

}  // namespace colosim
