// What the onboard view reads from the simulation (trainer/world_simulation.h).
#include <gtest/gtest.h>

#include "fixture.h"
#include "trainer/assets.h"
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

}  // namespace
}  // namespace colosim
