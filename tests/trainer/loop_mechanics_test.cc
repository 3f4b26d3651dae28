// Loops that need torque (issue 21): the shipped alpha loop with the tip hooked (up knob
// 2.5 rad, the scope's link held at both ends: the grip and the hook) and 15 cm withdrawn
// over 2-10 s. Withdrawal alone leaves the loop; rotation takes it out in one direction only.
// Which direction is the loop's handedness: today's start shape is a reverse alpha loop (its
// return limb behind the shaft), which comes out anticlockwise, in the model as in the clinic
// (docs/clinical-mechanics.md, session 22). The scenario is meant to become an alpha loop,
// so this test asserts the phenomenon, not the direction.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "trainer/assets.h"
#include "trainer/clinical_manoeuvres.h"
#include "trainer/scenario.h"
#include "trainer/start_state.h"
#include "trainer/world_simulation.h"

namespace colosim {
namespace {

// What the clinic sees with the loop: the withdrawal the loop does not give way to takes the
// tip back (21 cm along the colon's rest length for the 15 cm withdrawn, the sigmoid
// stretched behind it), while the turn that undoes the loop keeps the tip where it was (it
// even advances, 3 cm). The patient is the one of session 43: the contacts' coupling
// predictor (the colon and the scope feel each other's move within the step) and the
// retroperitoneal colon held firmer (attached lifters 5000 N/m per m, damped at half
// critical). On the patient before it (attached 1000, the contacts' lag) the loop's stay
// stood on the lag: with the predictor alone the writhe of no rotation ended at -0.47, past
// the half turn (docs/clinical-mechanics.md, session 42). Measured: writhe at 2 s -0.962; at
// 12 s none -0.994, clockwise -1.032, anticlockwise +0.421 (the straightened path's writhe);
// tip back 0.210, 0.215, -0.031 m.
TEST(LoopMechanics, WithTheTipHookedOnlyOneRotationUndoesTheLoop) {
  const Parameters patient = loadParameters(findScenario("sigmoid_untwist").params_path);
  const HookedUntwist none = hookedUntwist(patient, 0.0), cw = hookedUntwist(patient, -1.0),
                      ccw = hookedUntwist(patient, 1.0);  // the shipped expert turns anticlockwise
  std::printf("writhe at 2 s %.3f; at 12 s (tip back): none %.3f (%.3f m), clockwise %.3f (%.3f m), anticlockwise %.3f "
              "(%.3f m)\n",
              none.writhe_start, none.writhe_end, none.tip_back_m, cw.writhe_end, cw.tip_back_m, ccw.writhe_end,
              ccw.tip_back_m);
  ASSERT_GT(std::abs(none.writhe_start), 0.8) << "an alpha loop to begin with";
  EXPECT_GT(std::abs(none.writhe_end), 0.8) << "withdrawal alone leaves the loop whole, not half spun out";
  EXPECT_TRUE(none.stays());
  ASSERT_NE(cw.stays(), ccw.stays()) << "one direction of 1.25 turns takes it out, the other does not";
  const HookedUntwist& undoing = cw.stays() ? ccw : cw;
  EXPECT_LT(undoing.tip_back_m, 0.08) << "undoing the loop keeps the hooked tip";
  EXPECT_GT(none.tip_back_m, undoing.tip_back_m + 0.10) << "withdrawal alone takes the tip back instead";
  EXPECT_EQ(none.limited_steps + cw.limited_steps + ccw.limited_steps, 0);
}

// Pleating (issue 21): the colon gathered onto the scope by a hooked withdrawal.
// free_insertion's script to 30 s (the tip near the far end of the sigmoid), then the up knob
// to 2.5 rad over 1 s and 15 cm withdrawn over 8 s with a quarter turn clockwise
// (kHookedWithdrawalTurn_rad), held 3 s. On a candidate patient: the one patient
// (default.json) with the haustral folds in the contact wall (depth 0.25, the renderer's) and
// a colon that pleats under axial compression (compression fraction 0.05). With the folds
// the hooked tip holds the colon and the sigmoid shortens onto the scope to below the issue's
// 80 % of its rest length; on the paper's smooth tube (fold depth 0) the tip slides back along
// it. Measured: 0.779 (tip -0.3 cm), the smooth tube 0.940 (8.1 cm back). Without
// the turn the twist that setting the hook stores spun the tip off its fold 5.5 s into the
// withdrawal (8 cm back, 0.864 at the least); on the patient before session 43 (attached
// 1000) the hook held without it. Not yet the shipped patient: docs/clinical-mechanics.md,
// sessions 22-23 and 43.
HookedWithdrawal hookedWithdrawalOn(Parameters params, double fold_depth, double compression_fraction) {
  params.colon.haustral_fold_depth = fold_depth;
  params.colon.compression_stiffness_fraction = compression_fraction;
  return hookedWithdrawal(params);
}

TEST(Pleating, AHookedWithdrawalGathersTheSigmoidOntoTheScope) {
  const Parameters patient = loadParameters(findScenario("free_insertion").params_path);
  const HookedWithdrawal folds = hookedWithdrawalOn(patient, 0.25, 0.05), smooth = hookedWithdrawalOn(patient, 0.0, 0.05);
  std::printf("sigmoid present/rest: folds %.3f -> least %.3f, tip back %.3f m, %ld limited steps; smooth tube %.3f -> "
              "%.3f, tip back %.3f m\n",
              folds.sigmoid_before, folds.sigmoid_least, folds.tip_back_m, folds.limited_steps, smooth.sigmoid_before,
              smooth.sigmoid_least, smooth.tip_back_m);
  // The gathering must not stand on a clamped force (before the threading contacts were
  // made continuous, one flickered in for one step here past the 20 N limit).
  EXPECT_EQ(folds.limited_steps, 0);
  EXPECT_LT(folds.tip_back_m, 0.05) << "the hooked tip holds: it slides back less than a third of the 15 cm";
  EXPECT_GT(smooth.tip_back_m, 0.05) << "on a smooth tube the hook slides back more than a third of the 15 cm";
  EXPECT_LT(folds.sigmoid_least, smooth.sigmoid_least - 0.05) << "the held colon is gathered onto the scope";
  EXPECT_LT(folds.sigmoid_least, 0.80) << "the issue's pleating: below 80 % of the sigmoid's rest length";
}

// The loop's writhe is measured every 10 ms and held in between (it cost 15 % of a run at
// every step): on the shipped untwist it changes only at multiples of 10 steps, and a run
// restarted reads a fresh value at once.
TEST(LoopMechanics, TheWritheIsSampledEveryTenSteps) {
  const Scenario sc = findScenario("sigmoid_untwist");
  WorldSimulation sim(sc);
  double last = sim.telemetry().loop_writhe;
  int changes = 0;
  for (long k = 1; k <= 1500; ++k) {
    sim.step(scriptedInput(sc.script, static_cast<double>(k - 1) * sim.dt_s()));
    const double w = sim.telemetry().loop_writhe;
    if (w != last) {
      EXPECT_EQ(k % 10, 0) << "step " << k;
      ++changes;
    }
    last = w;
  }
  EXPECT_GT(changes, 100);
  EXPECT_GT(std::abs(last), 0.5) << "the shipped loop at 1.5 s";
  sim.restart(startSpecOf(sc));
  EXPECT_NE(sim.telemetry().loop_writhe, last) << "measured again at the restart";
}

}  // namespace
}  // namespace colosim
