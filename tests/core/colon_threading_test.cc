// Threading contacts (core/colon_threading.h): the colon's control points between two
// slices held around the scope's axis.
#include "core/colon_threading.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "core/colon_step.h"
#include "core/contact_tracking.h"
#include "core/scope_step.h"
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

// The slice of the chain whose track is nearest control point i (slices_per_segment 1).
int sliceNear(const WorldState& s, int i) {
  int best = 0;
  for (int k = 0; k < s.scope.inside; ++k) {
    const WallTrack& t = s.slice_track[static_cast<size_t>(k)];
    const WallTrack& b = s.slice_track[static_cast<size_t>(best)];
    if (std::abs(t.colon_segment + t.p - i) < std::abs(b.colon_segment + b.p - i)) best = k;
  }
  return best;
}

// The one threading contact found at control point i (fails the test when there is none).
WallContact contactAt(const Threaded& t, int i) {
  std::vector<WallContact> found;
  findThreadingContacts(t.m, t.s, found);
  for (const WallContact& c : found)
    if (c.colon_segment == i) return c;
  ADD_FAILURE() << "no threading contact at control point " << i;
  return WallContact();
}

// A control point sitting on a slice's track is counted in one of the slice's two chords
// or the other as the track moves by a hair: its contact must not change. With the scope
// bent at that slice and the point beside it but a little distal, the chord's nearest
// point jumped from the proximal chord's end to the distal chord's interior (a gathered
// sigmoid: one step at 1.2 mm, 36 N). Where the colon is gathered onto the scope, control
// points lie within millimetres of one slice and its track can flip among them for a step
// (session 23: 11.97 -> 9.999 at the rectosigmoid junction): a control point bracketed
// before and after the flip keeps its contact too, its axis point being the nearest point
// of the chords around it, not a point placed by the tracks (with the axis interpolated by
// track, the contact moved 1-2 mm and asked 20-36 N in that step).
TEST(ColonThreading, AControlPointIsHeldTheSameWhicheverChordItsTrackCountsItIn) {
  Threaded t(30000);
  ASSERT_EQ(t.m.scope.params.slices_per_segment, 1);
  const int i = 10;
  const int k = sliceNear(t.s, i);
  ASSERT_GT(k, 0);
  ASSERT_LT(k, t.s.scope.inside - 1);
  // Bend the scope at slice k by 5 mm (+x) and put the point beside it, 3 mm distal, 4 mm past
  // the threshold on the other side (-x).
  t.s.scope.p_W[k].x() += 0.005;
  const Vec3 c = sliceCentre(t.m.scope, t.s.scope, k, 0);
  t.s.colon.q.col(i) = c + Vec3(-(t.threshold_m(i) + 0.004), 0, 0) + 0.003 * (c - sliceCentre(t.m.scope, t.s.scope, k + 1, 0)).normalized();
  auto contactWithTrack = [&](int segment, double p) {
    t.s.slice_track[static_cast<size_t>(k)] = {segment, p};
    return contactAt(t, i);
  };
  const WallContact below = contactWithTrack(i - 1, 1.0 - 1e-9), above = contactWithTrack(i, 1e-9);
  EXPECT_GT(below.depth_m, 0.001);
  EXPECT_NEAR(below.depth_m, above.depth_m, 1e-8);
  EXPECT_LT((below.p_W_point - above.p_W_point).norm(), 1e-8);
  // The track flipped by most of a control-point spacing either way: i between slice k and
  // the next towards the tip, then between the slice before k and k.
  const WallContact before = contactWithTrack(i - 1, 0.7), after = contactWithTrack(i, 0.3);
  EXPECT_EQ(before.depth_m, after.depth_m);
  EXPECT_EQ((before.p_W_point - after.p_W_point).norm(), 0.0);
  EXPECT_EQ(before.scope_segment, after.scope_segment);
  // And the scope's axis there is the point of the slice's two chords nearest the control
  // point (brute force over both chords).
  const Vec3 q = t.s.colon.q.col(i);
  double nearest_m = 1e9;
  for (const int other : {k - 1, k + 1}) {
    const Vec3 o = sliceCentre(t.m.scope, t.s.scope, other, 0);
    for (int j = 0; j <= 100000; ++j) nearest_m = std::min(nearest_m, (c + (j * 1e-5) * (o - c) - q).norm());
  }
  EXPECT_NEAR((below.p_W_point - q).norm(), nearest_m, 1e-7);
}

// The tip's slice passing a control point pressed into the wall hands its contact over:
// its weight grows from 0 with the tip's further travel, to 1 half a spacing on, where a
// full contact would appear at once (0.7 mm, 22 N in one step of free_insertion).
TEST(ColonThreading, TheTipHandsOverTheControlPointItHasJustPassed) {
  Threaded t(30000);
  const int tip = 0;
  const WallTrack at = t.s.slice_track[tip];
  const int i = static_cast<int>(std::floor(at.colon_segment + at.p));  // just passed by the tip
  ASSERT_GT(i, 1);
  t.s.colon.q.col(i).x() += t.threshold_m(i) + 0.01;
  for (const double past : {0.05, 0.25, 0.45, 0.6, 0.9}) {
    t.s.slice_track[tip] = {i, past};
    const WallContact c = contactAt(t, i);
    EXPECT_LE(c.scope_segment, 1) << "on the tip's segment or the one behind it";
    EXPECT_NEAR(c.weight, std::min(1.0, past / 0.5), 1e-12) << past;
  }
  // Not yet passed: nothing.
  t.s.slice_track[tip] = {i - 1, 0.95};
  std::vector<WallContact> found;
  findThreadingContacts(t.m, t.s, found);
  for (const WallContact& c : found) EXPECT_NE(c.colon_segment, i);
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
    applyThreadingContacts(t.m, t.s, 1e-3);
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

// Beyond the point limit the threading contact is limited like a wall contact, and the
// step's report names it: a threading contact, at its control point, its depth.
TEST(ColonThreading, ALimitedContactIsReportedAsThreading) {
  Threaded t(30000);
  const double depth_m = 0.003;  // 90 N at 30,000 N/m: over the 60 N point limit
  t.s.colon.q.col(10).x() += t.threshold_m(10) + depth_m;
  t.s.contact_limit = ContactLimitReport();
  applyThreadingContacts(t.m, t.s, 1e-3);
  EXPECT_EQ(t.s.contact_limit.limited, 1);
  EXPECT_EQ(t.s.contact_limit.worst.kind, ContactLimitReport::Worst::Kind::kThreading);
  EXPECT_EQ(t.s.contact_limit.worst.colon_segment, 10);
  EXPECT_NEAR(t.s.contact_limit.worst.depth_m, depth_m, 1e-9);
  EXPECT_NEAR(t.s.contact_limit.worst.asked_N, 30000 * depth_m, 1e-6);
  EXPECT_NEAR(t.s.max_wall_force_N, t.m.contact.max_point_force_N, 1e-9);
}

// The threading stop of control point i in a state's last step.
const WorldState::ThreadingStop& stopAt(const WorldState& s, int i) {
  const auto it = std::find_if(s.threading_stops.begin(), s.threading_stops.end(),
                               [i](const WorldState::ThreadingStop& st) { return st.point == i; });
  static const WorldState::ThreadingStop none;
  EXPECT_NE(it, s.threading_stops.end()) << "no stop at control point " << i;
  return it != s.threading_stops.end() ? *it : none;
}

// The threading stop (stopThreading): a control point 1 mm short of a contact, closing on
// it at 2 m/s (the colon swept sideways past the scope), would go about 1 mm beyond the
// wall's thickness in one 1 ms step: the penalty is found only at the start of the step.
// The stop holds it where the spring asks ContactParams::threading_stop_force_N (10 N:
// 0.33 mm), and the scope takes the other half of the impulse (its axis point there moves
// towards the control point). A control point that is not closing that fast is left bit
// for bit.
TEST(ColonThreading, TheStopHoldsAControlPointClosingFasterThanOneStepAllows) {
  const double dt = 1e-3;
  const int i = 10;
  auto run = [&](double speed_m_per_s, bool stop, double* depth_after_m, Vec3* axis_after_W) {
    Threaded t(30000);
    t.s.colon.q.row(0).array() += t.threshold_m(i) - 0.001;  // the colon beside the scope
    t.s.colon.v.row(0).setConstant(speed_m_per_s);           // and swept sideways, away from its axis
    t.s.colon.loads.clear();
    t.s.scope.loads.clear();
    applyThreadingContacts(t.m, t.s, dt);
    EXPECT_TRUE(t.s.threading.empty());  // no contact at the start
    stepColon(t.m.colon, t.s.colon, dt);
    HandleInput in = t.s.scope.input;
    stepScope(t.m.scope, t.s.scope, in, dt);
    if (stop) stopThreading(t.m, t.s, dt);
    std::vector<WallContact> found;
    findThreadingContacts(t.m, t.s, found);
    *depth_after_m = 0;
    for (const WallContact& c : found)
      if (c.colon_segment == i) *depth_after_m = c.depth_m;
    const WorldState::ThreadingStop& st = stopAt(t.s, i);
    const int k = st.scope_segment;
    *axis_after_W = t.s.scope.p_W[k] + t.s.scope.R_WS[k] * (t.s.scope.start.R_WS[k].transpose() * st.lever_W);
    return t.s;
  };
  double free_m = 0, held_m = 0, slow_free_m = 0, slow_held_m = 0;
  Vec3 axis_free, axis_held, a, b;
  run(2.0, false, &free_m, &axis_free);
  const WorldState s = run(2.0, true, &held_m, &axis_held);
  EXPECT_GT(free_m, 0.0008);  // the penalty alone: about 1 mm beyond (0.86 mm: the lifters)
  const Threaded model(30000);
  const double allowed_m = model.m.contact.threading_stop_force_N / 30000.0;
  EXPECT_EQ(stopAt(s, i).allowed_m, allowed_m);  // a full-weight contact
  EXPECT_GT(stopAt(s, i).impulse_Ns, 0.0);
  EXPECT_LT(held_m, allowed_m + 2e-5);
  EXPECT_LT(held_m, 0.5 * free_m);  // (its neighbours' stops hold it too: 0.2 mm)
  EXPECT_GT(axis_held.x() - axis_free.x(), 1e-6);  // the scope pulled towards the point (+x)
  // Slow: 0.5 m/s ends about 0.5 mm short of the contact, and nothing is stopped.
  const WorldState s_free = run(0.5, false, &slow_free_m, &a);
  const WorldState s_held = run(0.5, true, &slow_held_m, &b);
  EXPECT_EQ(hashWorldState(s_free), hashWorldState(s_held));
  for (const WorldState::ThreadingStop& st : s_held.threading_stops) EXPECT_EQ(st.impulse_Ns, 0.0);
}

}  // namespace
}  // namespace colosim
