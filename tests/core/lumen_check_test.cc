// The contact-topology measures (core/lumen_check.h) and the closed-joint threading
// (core/world.h threadScopeAlongColon) on small colons written inline.
#include "core/lumen_check.h"

#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "core/tension_law.h"
#include "tests/core/small_colons.h"

namespace colosim {
namespace {

// A quarter circle of radius `bend_m` after 0.1 m of straight colon down -z from the anus.
Points bent(double bend_m) {
  std::vector<Vec3> pts;
  for (double z = 0; z <= 0.1 + 1e-9; z += 0.01) pts.emplace_back(0, 0, -z);
  for (int i = 1; i <= 12; ++i) {
    const double a = 0.5 * M_PI * i / 12;
    pts.emplace_back(bend_m * (1 - std::cos(a)), 0, -0.1 - bend_m * std::sin(a));
  }
  for (int i = 1; i <= 10; ++i) pts.emplace_back(bend_m + 0.01 * i, 0, -0.1 - bend_m);
  Points q(3, static_cast<int>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) q.col(static_cast<int>(i)) = pts[i];
  return q;
}

// Scratch for checkLumen.
std::vector<double> arc;

// Tracks as the paper's scan leaves them: every point and slice centre on the colon
// location nearest it (unambiguous on these colons).
void trackNearest(const WorldModel& m, WorldState& s) {
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  const int slices = m.scope.params.slices_per_segment;
  auto nearest = [&](const Vec3& x) {
    const ClosestPoint c = closestPointOnSpline(s.colon.q, x);
    return WallTrack{c.segment, c.p};
  };
  for (int k = 0; k < s.scope.inside; ++k) {
    for (int i = 0; i < P; ++i) s.track[k * P + i] = nearest(interactionPoint(m.scope, s.scope, k, i));
    for (int sl = 0; sl < slices; ++sl) s.slice_track[k * slices + sl] = nearest(sliceCentre(m.scope, s.scope, k, sl));
  }
  for (size_t f = 0; f < m.scope.tip_face_points_S.size(); ++f)
    s.track[m.scope.segment_count * P + f] = nearest(tipFacePoint(m.scope, s.scope, static_cast<int>(f)));
}

TEST(LumenCheck, AScopeAlongTheCentrelineIsInsideWithContinuousTracks) {
  const WorldModel m = smallWorld(straightDown(0.6), 0.02);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.4);
  trackNearest(m, s);
  const LumenCheck c = checkLumen(m, s, arc);
  EXPECT_LT(c.track_jump_m, 1e-9);
  EXPECT_EQ(c.wall_penetration_m, 0.0);
  EXPECT_FALSE(c.lumen_exit);
}

TEST(LumenCheck, ASliceTrackedOnAFarPartIsAJumpAndAnExit) {
  const WorldModel m = smallWorld(straightDown(0.6), 0.02);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.4);
  trackNearest(m, s);
  // Slice 10 (one per segment) tracked 0.15 m deeper along the colon than it is.
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  const WallTrack t = s.slice_track[10];
  s.slice_track[10] = {t.colon_segment + 10, t.p};
  for (int i = 0; i < P; ++i) s.track[10 * P + i] = {t.colon_segment + 10, t.p};
  const LumenCheck c = checkLumen(m, s, arc);
  // Its neighbours are 0.15 m -+ h away in arclength: the jump beyond h is 0.15 m.
  EXPECT_NEAR(c.track_jump_m, 0.15, 1e-6);
  // Its centre is 0.15 m from the tracked centreline point, far outside the 2 cm lumen;
  // its points sqrt(0.15^2 + r^2) from it.
  EXPECT_TRUE(c.lumen_exit);
  EXPECT_NEAR(c.wall_penetration_m, std::hypot(0.15, m.scope.radius_m) - 0.02, 1e-6);
}

TEST(LumenCheck, ASegmentPushedIntoTheWallPenetratesByWhatItIsOut) {
  const WorldModel m = smallWorld(straightDown(0.6), 0.02);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.4);
  s.scope.p_W[5] += Vec3(0.03, 0, 0);  // 3 cm sideways: its axis 1 cm beyond the wall
  trackNearest(m, s);
  const LumenCheck c = checkLumen(m, s, arc);
  EXPECT_TRUE(c.lumen_exit);
  EXPECT_NEAR(c.wall_penetration_m, 0.03 + m.scope.radius_m - 0.02, 1e-6);
  EXPECT_LT(c.track_jump_m, 1e-6);  // still tracked beside its neighbours
}

TEST(Threading, JointsStartClosedOnABend) {
  // A bend of 2 cm radius, tighter than the scope's joints follow unloaded: segments
  // centred on arclength chords used to overlap there by ~0.35 mm.
  for (double bend_m : {0.02, 0.05}) {
    const WorldModel m = smallWorld(bent(bend_m), 0.02);
    WorldState s = makeWorldState(m);
    threadScopeAlongColon(m, s, 0.18);  // the colon is 0.23-0.28 m long: the tip stays short of its end
    ASSERT_GT(s.scope.inside, 10);
    const double h = m.scope.h_m;
    for (int k = 0; k + 1 <= s.scope.inside; ++k) {
      const Vec3 distal_end_of_next = s.scope.p_W[k + 1] + 0.5 * h * s.scope.R_WS[k + 1].col(2);
      const Vec3 proximal_end = s.scope.p_W[k] - 0.5 * h * s.scope.R_WS[k].col(2);
      EXPECT_LT((proximal_end - distal_end_of_next).norm(), 1e-9) << "bend " << bend_m << " joint " << k;
    }
    // Every joint on the centreline: the segments' ends lie within 1 um of the colon's axis.
    for (int k = 0; k < s.scope.inside; ++k) {
      const Vec3 end = s.scope.p_W[k] + 0.5 * h * s.scope.R_WS[k].col(2);
      EXPECT_LT(closestPointOnSpline(s.colon.q, end).distance, 1e-6) << "bend " << bend_m << " segment " << k;
    }
  }
}

}  // namespace
}  // namespace colosim
