// Threading contacts (core/colon_threading.h): the colon's control points between two
// slices held around the scope's axis.
#include "core/colon_threading.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/contact_tracking.h"
#include "tests/core/every_segment.h"
#include "tests/core/small_colons.h"

namespace colosim {
namespace {

// A straight colon (radius 2 cm) with the scope threaded 0.4 m along its axis and tracked.
struct Threaded {
  WorldModel m;
  WorldState s;
  explicit Threaded(double threading_stiffness_N_per_m) : m(smallWorld(straightDown(0.6), 0.02)) {
    m.contact.threading_stiffness_N_per_m = threading_stiffness_N_per_m;
    s = makeWorldState(m);
    threadScopeAlongColon(m, s, 0.4);
    ContactTracker tracker(m);
    EverySegment candidates;
    tracker.updateCubics(s.colon);
    tracker.trackWallContacts(m, s, candidates);
  }
  // The threshold beyond which a control point's offset from the axis is a contact [m].
  double threshold_m(int i) const { return m.colon.radius_m(i) - m.scope.radius_m + m.contact.wall_thickness_m; }
};

TEST(ColonThreading, NoneWhereTheScopeIsInsideTheLumen) {
  Threaded t(30000);
  ASSERT_GT(t.s.scope.inside, 20);
  std::vector<WallContact> found;
  findThreadingContacts(t.m, t.s, found);
  EXPECT_TRUE(found.empty());
  // Moved sideways to just short of the threshold: still none.
  t.s.colon.q.col(10).x() += t.threshold_m(10) - 1e-6;
  findThreadingContacts(t.m, t.s, found);
  EXPECT_TRUE(found.empty());
}

// A control point between two slices pushed off the scope's axis by more than the lumen
// radius less the scope's radius plus the wall's thickness: one contact at that point, its
// depth what lies beyond, its normal from the point towards the axis, on the axis at the
// point's height, on the scope segment of a slice beside it.
TEST(ColonThreading, AControlPointOffTheScopeBetweenTwoSlicesIsHeld) {
  Threaded t(30000);
  const int i = 10;
  const double offset_m = t.threshold_m(i) + 0.004;
  t.s.colon.q.col(i).x() += offset_m;
  std::vector<WallContact> found;
  findThreadingContacts(t.m, t.s, found);
  ASSERT_EQ(found.size(), 1u);
  const WallContact& c = found[0];
  EXPECT_EQ(c.colon_segment, i);
  EXPECT_EQ(c.p, 0.0);
  EXPECT_NEAR(c.depth_m, 0.004, 1e-9);
  EXPECT_LT((c.normal_W - Vec3(-1, 0, 0)).norm(), 1e-9);
  EXPECT_LT((c.p_W_point - Vec3(0, 0, t.s.colon.q(2, i))).norm(), 1e-9);
  EXPECT_LT((c.p_W_centre - t.s.colon.q.col(i)).norm(), 1e-15);
  // On the segment of one of the two slices on either side of it.
  EXPECT_LT((t.s.scope.p_W[c.scope_segment] - c.p_W_point).norm(), t.m.scope.h_m);
}

// Beyond the tip no slice brackets a control point: nothing holds it there.
TEST(ColonThreading, NothingBeyondTheTip) {
  Threaded t(30000);
  const int beyond = 35;  // 0.525 m along the colon, the tip at about 0.4 m
  t.s.colon.q.col(beyond).x() += 0.05;
  std::vector<WallContact> found;
  findThreadingContacts(t.m, t.s, found);
  EXPECT_TRUE(found.empty());
}

// The loads: eq. 7 with the threading stiffness (no second backing) on both bodies,
// opposite, in the implicit solves with that stiffness; with the stiffness 0 (the paper's
// wall) none.
TEST(ColonThreading, LoadsAreTheThreadingSpringOnBothBodiesOpposite) {
  for (double k : {0.0, 30000.0}) {
    Threaded t(k);
    const double depth_m = 0.0005;  // 15 N at 30,000 N/m: under the 20 N point limit
    t.s.colon.q.col(10).x() += t.threshold_m(10) + depth_m;
    t.s.colon.loads.clear();
    t.s.scope.loads.clear();
    applyThreadingContacts(t.m, t.s);
    if (k == 0) {
      EXPECT_TRUE(t.s.threading.empty());
      EXPECT_TRUE(t.s.colon.loads.empty());
      continue;
    }
    ASSERT_EQ(t.s.threading.size(), 1u);
    ASSERT_EQ(t.s.colon.loads.size(), 1u);
    ASSERT_EQ(t.s.scope.loads.size(), 1u);
    const Vec3 f_scope = t.s.scope.loads[0].force_N;
    EXPECT_NEAR(f_scope.x(), k * depth_m, 1e-9);  // the scope is pulled towards the point (+x), at rest
    EXPECT_NEAR(f_scope.y(), 0.0, 1e-12);
    EXPECT_NEAR(f_scope.z(), 0.0, 1e-12);
    EXPECT_LT((t.s.colon.loads[0].force_N + f_scope).norm(), 1e-12);
    EXPECT_EQ(t.s.colon.loads[0].segment, 10);
    EXPECT_NEAR(t.s.colon.loads[0].stiffness_N_per_m(0, 0), k, 1e-9);
    EXPECT_NEAR(t.s.max_wall_force_N, k * depth_m, 1e-9);
  }
}

}  // namespace
}  // namespace colosim
