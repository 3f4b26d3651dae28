// What the onboard view reads from the simulation (trainer/world_simulation.h).
#include <gtest/gtest.h>

#include "fixture.h"
#include "trainer/assets.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

namespace colosim {
namespace {

// Red-out reads the wall the camera sees. With the haustral folds in the contact wall, the
// lumen's radius is narrowed at every other control point; the renderer draws the
// anatomy's wall with thin folds of its own. A lens 4 mm short of a point between the two
// walls at a fold is not red; beyond the anatomy's wall it is.
TEST(ViewTelemetry, RedOutReadsTheAnatomysWallNotTheContactFolds) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  p.colon.haustral_fold_depth = 0.25;
  const ColonModel colon = loadColonModel(test::asset("anatomy/adult_pelvic_rectum.json"), p);
  const Points& q = colon.q_rest;
  int k = colon.n / 2;
  while (k < colon.n - 2 && !(colon.radius_m(k) < colon.smooth_radius_m(k))) ++k;
  ASSERT_LT(k, colon.n - 2) << "a fold";
  const Vec3 along = (q.col(k + 1) - q.col(k - 1)).normalized();
  Vec3 side = along.cross(Vec3(0, 0, 1));
  if (side.norm() < 0.1) side = along.cross(Vec3(1, 0, 0));
  side.normalize();
  const double folded_m = colon.radius_m(k), anatomy_m = colon.smooth_radius_m(k);
  for (const auto& [offset_m, red] : {std::pair{0.5 * (folded_m + anatomy_m), false},
                                       std::pair{anatomy_m + 0.0005, true}, std::pair{0.5 * folded_m, false}}) {
    const Vec3 ahead = q.col(k) + offset_m * side;
    const Vec3 tip = ahead - 0.004 * along;
    EXPECT_EQ(lensAgainstWall(colon, q, k, tip, along), red) << offset_m << " m off the centreline";
  }
}

// A replay of a recording measures only what it compares (measureHandleAndLoopOnly): the
// state stays the same bit for bit, and so do the handle force and torque, the tip and the
// coronal loop, step for step, through the shipped untwist's loop (2 s).
TEST(ViewTelemetry, MeasuringOnlyTheHandleAndTheLoopLeavesTheStateAndThoseValues) {
  const Scenario sc = findScenario("sigmoid_untwist");
  WorldSimulation full(sc), light(sc);
  light.measureHandleAndLoopOnly(true);
  int looped = 0;
  for (long k = 1; k <= 2000; ++k) {
    const HandleInput in = scriptedInput(sc.script, static_cast<double>(k - 1) * full.dt_s());
    full.step(in);
    light.step(in);
    ASSERT_EQ(full.stateHash(), light.stateHash()) << "step " << k;
    const Telemetry a = full.telemetry(), b = light.telemetry();
    ASSERT_EQ(a.handle_force_N, b.handle_force_N) << "step " << k;
    ASSERT_EQ(a.handle_torque_Nm, b.handle_torque_Nm) << "step " << k;
    ASSERT_EQ(a.tip_position_m, b.tip_position_m) << "step " << k;
    ASSERT_EQ(a.loop_turns, b.loop_turns) << "step " << k;
    looped += a.loop_turns != 0;
    EXPECT_EQ(b.mesentery_stretch, Telemetry().mesentery_stretch);  // not measured
  }
  EXPECT_GT(looped, 100) << "the loop was there to be measured";
}

}  // namespace
}  // namespace colosim
