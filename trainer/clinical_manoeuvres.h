// Two manoeuvres of issue 21's mechanics, run on any patient (parameter set): the hooked
// untwist, which asks whether the loop needs torque, and the hooked withdrawal, which asks
// whether the colon pleats onto the scope. The tests (tests/trainer/loop_mechanics_test.cc)
// hold them on the shipped patient; build/tools/trainer_patient_map runs them on candidate
// patients (docs/clinical-mechanics.md, session 29).
#pragma once

#include "trainer/assets.h"
#include "trainer/scenario.h"

namespace colosim {

/// `sigmoid_untwist`'s loop with the tip hooked (the up knob at 2.5 rad from the start, the
/// script's steering replaced) and its 15 cm withdrawal over 2-10 s, the script's rotation
/// scaled by rotation_scale (1: the shipped expert's 1.25 turns, anticlockwise; 0: none; -1:
/// the same clockwise); 12 s.
struct HookedUntwist {
  double writhe_start = 0;    ///< the loop's writhe at the end of the set-up (2 s) [turns]
  double writhe_end = 0;      ///< 10 s after the withdrawal began (12 s) [turns]
  double peak_torque_Nm = 0;  ///< largest |handle torque| [N m]
  /// How far the hooked tip slid back along the colon from 2 s to 12 s (rest arclength,
  /// positive back) [m]: a hook that holds keeps it near 0; a withdrawal the loop does not
  /// give way to takes the tip back instead.
  double tip_back_m = 0;
  long limited_steps = 0;     ///< steps in which a solver or contact limit engaged
  /// The loop of the start is still there: the same handedness, at least half a turn.
  bool stays() const;
};
HookedUntwist hookedUntwist(const Parameters& params, double rotation_scale);

/// The hand's turn during a hooked withdrawal [rad]: a quarter turn clockwise, as the hand
/// withdraws with clockwise torque. Setting the hook stores twist in the shaft (the bent tip
/// rolls towards the lumen's curve: 0.15 N m on the handle); a hand that holds the handle
/// still while withdrawing keeps it, and on a patient whose descending colon is held firmly
/// the stored twist spins the tip off its fold and the hook lets go (attached lifters
/// 5000 N/m per m: 8 cm back, 5.5 s into the withdrawal). Turned by 1-2 rad the hook holds on
/// the shipped patient and on the firmer ones; 3 rad overturns it (docs/clinical-mechanics.md,
/// session 43).
constexpr double kHookedWithdrawalTurn_rad = 1.5707963267948966;

/// `free_insertion`'s script to 30 s (the tip near the far end of the sigmoid), then the up
/// knob to 2.5 rad over 1 s, withdraw_m withdrawn over withdraw_s while the handle turns by
/// turn_rad (+ clockwise seen by the operator), held 3 s.
struct HookedWithdrawal {
  double sigmoid_before = 0;  ///< present/rest length of the sigmoid when the hook is set [-]
  double sigmoid_least = 0;   ///< its least during the withdrawal and hold [-]
  double tip_back_m = 0;      ///< how far the tip slid back along the colon (rest arclength) [m]
  long limited_steps = 0;     ///< steps in which a solver or contact limit engaged (from 30 s)
};
HookedWithdrawal hookedWithdrawal(const Parameters& params, double withdraw_m = 0.15, double withdraw_s = 8.0,
                                  double turn_rad = kHookedWithdrawalTurn_rad);

/// The abuse script `extreme_all` (everything at once) with its script's times and knob
/// angles scaled: the withdrawal at 1 / time_scale m/s, the knobs through knob_scale of their
/// range. The extreme tests and trainer_patient_map --abuse run its variants.
Scenario everythingAtOnce(double time_scale, double knob_scale);

}  // namespace colosim
