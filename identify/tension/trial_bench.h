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
// Two of those "other" forms (the set with a yield strain, two relaxation times) have since
// become forms of colosim's laws. The harder forms (forms = kHarder) are forms no law of
// colosim has; each seed draws one form per effect (the same in every class):
//
//   effect              harder forms (one of two per seed)
//   strain_stiffening   power law: Fe = EA x (1 + c x^p), p 1.2-4
//                       toe and linear region: tangent EA up to x_t, rising linearly to
//                         R EA over a width w, R EA beyond (linear, unlike any exponential)
//   stress_relaxation   Fung's box spectrum: 24 Maxwell branches of equal weight, times
//                         log-spaced over [tau_lo, tau_hi] (0.3-1 s to 30-100 s)
//                       4-6 Maxwell branches of drawn weights at log-uniform times in 0.3-100 s
//   cyclic_softening    damage that partly recovers at rest (whenever the strain is not
//                         rising): it tends to d* = d_inf (1 - exp(-driver / scale)) while
//                         loading and relaxes towards (1 - q) d* with time constant tau_rec
//                         otherwise; the driver is the accumulated loading strain or the
//                         largest strain (drawn)
//   permanent_set       a ratchet that shakes down: e_p = E (1 - exp(-a_y / a_s)), a_y the
//                         loading strain accumulated above a yield strain, so repeated
//                         cycles to one amplitude keep adding set, each less than the last
//                         (1-3 e-folds over the test; colosim's ratchet adds the same each time)
//                       recovering in slack: e_p rises to r max(0, e - e_y) while loading and
//                         relaxes towards (1 - q) of r max(0, e_max - e_y) while the sample is
//                         slack (e < e_p), time constant 1-4 s
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
enum class TrialForms { kOther, kOwn, kHarder };

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
  double set_yield_strain = 0;  ///< e_y (other and harder forms) [-]
  // Harder forms (kHarder): which form of each effect, and its own parameters.
  std::string stiff_form;     ///< "power" or "toe_linear"
  std::string relax_form;     ///< "box_spectrum" or "branches"
  std::string soften_form;    ///< "recovering_accumulated" or "recovering_largest"
  std::string set_form;       ///< "shakedown_ratchet" or "recovering"
  double power_c = 0, power_p = 2;   ///< Fe = EA x (1 + c x^p) [-], [-]
  double toe_strain = 0, toe_width = 0, linear_ratio = 1;  ///< x_t [-], w [-], R [-]
  std::vector<double> prony_g, prony_tau_s;  ///< the Maxwell branches: weights [-], times [s]
  double soften_q = 0;        ///< recoverable fraction of the damage [-]
  double soften_rec_tau_s = 30;   ///< recovery time constant at rest [s]
  double soften_reload_strain = 0.02;  ///< loading strain over which damage returns [-]
  double set_ratchet_c = 0;   ///< set per unit of loading strain above e_y, at the start [-]
  double set_shakedown_strain = 1;  ///< a_s: loading strain above e_y per e-fold of the ratchet's slowing [-]
  double set_q = 0;           ///< recoverable fraction of the set in slack [-]
  double set_rec_tau_s = 2;   ///< its time constant [s]
  /// A short name of the drawn forms of the hidden effects, e.g. "power+box_spectrum"
  /// (other and own forms: "other" / "own").
  std::string formNames() const;
};

/// Draws a trial: protocol, law and noise from the ranges in trial_bench.cc. The same seed
/// gives the same protocol and noise whatever the effects.
TrialSpec drawTrialSpec(uint64_t seed, const std::vector<std::string>& effects, TrialForms forms);

/// Runs the bench (a 2 ms grid, sampled at the drawn irregular times) and returns the test
/// as a file would hold it.
TensionTest generateTrialTest(const TrialSpec& spec);

}  // namespace colosim
