// A tension bench drawn independently of the laws colosim fits, for hidden-effect trials
// (issue 17, docs/identification-trials.md). The identification fits the effects of
// core/extended_tension_law.h; this bench hides other forms of the same effects, so that
// the trials measure what the identification does on data it was not built for:
//
//   effect              other form (the default)                 own form (forms = kOwn)
//   strain_stiffening   cubic: Fe = EA (x + k x^3)                 Fung: EA / b (exp(b x) - 1)
//   stress_relaxation   two Maxwell branches (tau ~1 s and ~30 s)  one branch
//   cyclic_softening    damage driven by the largest strain:       damage driven by the
//                       d = d_inf (1 - exp(-e_max / e_c))           accumulated loading strain
//   permanent_set       with a yield threshold:                    e_p = r e_max
//                       e_p = r max(0, e_max - e_y)
//
// The protocols are not the project generator's either: staircases with holds of 5-15 s
// (up, down and up again), or cycles of rising amplitude with holds, each at two loading
// rates; a second-order actuator (smoothed corners), sampling at 50-200 Hz with an
// irregular time base and jittered time stamps, a sensor offset, white and coloured noise
// of drawn sizes, an encoder quantised to 1 um.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "identify/tension/tension_test.h"

namespace colosim {

/// Which forms of the effects the bench hides.
enum class TrialForms { kOther, kOwn };

/// One drawn trial: what the bench hid and the parameters it used.
struct TrialSpec {
  std::vector<std::string> effects;   ///< hidden effects, in tensionEffectNames() order
  TrialForms forms = TrialForms::kOther;
  uint64_t seed = 0;
  std::string protocol;               ///< "staircase" or "rising_cycles"
  double sample_length_m = 0.18;      ///< rest length L [m]
  double max_strain = 0.5;            ///< largest commanded strain [-]
  double slow_speed_m_per_s = 3e-3, fast_speed_m_per_s = 12e-3;  ///< the two loading rates
  double actuator_tau_s = 0.1;        ///< time constant of the critically damped actuator [s]
  double sample_rate_hz = 100;        ///< nominal sampling rate [1/s]
  double offset_N = 0, white_sd_N = 0.03, coloured_sd_N = 0.01;
  // The law (unused parameters are left at their defaults).
  double ea_N = 20;           ///< EA: tangent at zero strain [N]
  double ec_Ns = 0.05;        ///< EC [N s]
  double fung_b = 0;          ///< own stiffening exponent [-]
  double cubic_k = 0;         ///< other stiffening: Fe = EA (x + k x^3) [-]
  double relax_g1 = 0, relax_tau1_s = 1, relax_g2 = 0, relax_tau2_s = 30;  ///< [-], [s]
  double soften_d_inf = 0;    ///< stiffness fraction lost at saturation [-]
  double soften_scale = 1;    ///< a_c (own) or e_c (other) [-]
  double set_ratio = 0;       ///< r [-]
  double set_yield_strain = 0;  ///< e_y (other form) [-]
};

/// Draws a trial: protocol, law and noise from the ranges in trial_bench.cc. The same seed
/// gives the same protocol and noise whatever the effects.
TrialSpec drawTrialSpec(uint64_t seed, const std::vector<std::string>& effects, TrialForms forms);

/// Runs the bench (a 2 ms grid, sampled at the drawn irregular times) and returns the test
/// as a file would hold it.
TensionTest generateTrialTest(const TrialSpec& spec);

}  // namespace colosim
