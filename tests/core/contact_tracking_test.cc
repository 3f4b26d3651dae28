#include "core/contact_tracking.h"

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "core/rotation.h"
#include "core/tension_law.h"
#include "tests/random_vec3.h"
#include "tests/core/every_segment.h"
#include "tests/core/small_colons.h"

namespace colosim {
namespace {

// Part A along +x from the origin to 0.2 m, a half turn, part B back along y = gap_m.
Points hairpin(double gap_m) {
  std::vector<Vec3> pts;
  for (double x = 0; x <= 0.20 + 1e-9; x += 0.01) pts.emplace_back(x, 0, 0);
  for (int i = 1; i < 6; ++i) {
    const double a = M_PI * i / 6;
    pts.emplace_back(0.20 + 0.5 * gap_m * std::sin(a), 0.5 * gap_m * (1 - std::cos(a)), 0);
  }
  for (double x = 0.20; x >= -1e-9; x -= 0.01) pts.emplace_back(x, gap_m, 0);
  Points q(3, static_cast<int>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) q.col(static_cast<int>(i)) = pts[i];
  return q;
}


TEST(ContactTracking, WalkReachesTheLocalMinimumAlongTheSpline) {
  const WorldModel m = smallWorld(straightDown(0.6), 0.02);
  std::vector<SegmentCubic> cubics;
  updateSegmentCubics(m.colon.q_rest, cubics);
  const Vec3 x(0.005, 0, -0.3);
  SplineLocation scan;
  for (int j = 0; j < static_cast<int>(cubics.size()); ++j) considerSegment(cubics, j, x, scan);
  for (int start : {0, 5, 30, 39}) {
    const SplineLocation walked = walkToNearest(cubics, x, start);
    EXPECT_NEAR(walked.d, scan.d, 1e-12) << "from segment " << start;
    EXPECT_NEAR(m.colon.arclengthAt(walked.j, walked.p), 0.3, 1e-9);
  }
  EXPECT_LT(walkToNearest(cubics, x, -1).j, 0);  // nothing tracked: no walk
}

// A point reached by walking along part A of a hairpin stays on A however far it is pushed
// towards B: 8 mm beyond A's wall (inside B's lumen), or deep in B's lumen. Walking from B
// it is on B. The paper's scan would take B every time (the nearer centreline).
TEST(ContactTracking, APointNeverChangesPartThroughTheWall) {
  const double r = 0.02, gap = 0.05;
  const WorldModel m = smallWorld(hairpin(gap), r);
  ContactTracker tracker(m);
  const ColonState rest = makeColonState(m.colon, 0);
  tracker.updateCubics(rest);
  EverySegment candidates;
  auto partAt = [&](const SplineLocation& at) { return m.colon.arclengthAt(at.j, at.p) < 0.2 ? 'A' : 'B'; };
  const SplineLocation on_a{10, 0.0};  // x = 0.1 m
  SplineLocation on_b;
  for (int j = 0; j + 1 < m.colon.n; ++j)
    if (m.colon.s_rest_m(j) > 0.25 && std::abs(rest.q(0, j) - 0.1) < 0.006) on_b = {j, 0.0};
  ASSERT_GE(on_b.j, 0);
  for (double y : {0.028, 0.031, 0.045}) {
    const Vec3 x(0.1, y, 0);
    EXPECT_EQ(partAt(tracker.nearestOnPart(m, x, on_a, 0, candidates)), 'A') << "y = " << y;
    EXPECT_EQ(partAt(tracker.nearestOnPart(m, x, on_b, 0, candidates)), 'B') << "y = " << y;
  }
}

// A pleat: the colon folded back and forth (a zig-zag of 1.5 cm chords within 2 cm of the
// scope's axis) stays near a point on the axis; the other arm of a hairpin 5 cm away is
// reached through its 0.2 m long arm and U-turn.
TEST(ContactTracking, TheColonStaysNearAPointThroughAPleatButNotRoundALoop) {
  std::vector<Vec3> zig;
  for (int i = 0; i < 12; ++i) zig.emplace_back(0.004 * i, (i % 2) ? 0.012 : -0.012, 0);
  Points q(3, static_cast<int>(zig.size()));
  for (size_t i = 0; i < zig.size(); ++i) q.col(static_cast<int>(i)) = zig[i];
  std::vector<SegmentCubic> cubics;
  updateSegmentCubics(q, cubics);
  const Vec3 x(0.02, 0, 0);
  EXPECT_TRUE(colonStaysNear(cubics, SplineLocation{0, 0.5}, SplineLocation{9, 0.5}, x, M_PI * 0.02));
  EXPECT_FALSE(colonStaysNear(cubics, SplineLocation{0, 0.5}, SplineLocation{9, 0.5}, x, 0.01));

  const WorldModel m = smallWorld(hairpin(0.05), 0.02);
  updateSegmentCubics(m.colon.q_rest, cubics);
  const Vec3 y(0.1, 0.025, 0);  // between the arms, opposite control point 10 of A
  int on_b = 0;
  while (!(m.colon.s_rest_m(on_b) > 0.25 && std::abs(m.colon.q_rest(0, on_b) - 0.1) < 0.006)) ++on_b;
  EXPECT_FALSE(colonStaysNear(cubics, SplineLocation{10, 0.0}, SplineLocation{on_b, 0.0}, y, M_PI * 0.02));
}

// Where the colon is gathered into a pleat (the start of a free sigmoid dragged down onto the
// scope at the top of a wider rectum, extreme_all), a point 1.5 mm inside the wide part's
// 21.3 mm lumen can lie 0.2 mm nearer the centreline of the narrower pleat (19.4 mm),
// outside its wall. It is inside the colon, with no contact. Rule 2 by distance alone (a
// nearer location of the same part takes over) put it 0.2 mm beyond the pleat's wall, 6 cm
// of colon away from its neighbours: a lumen exit.
TEST(ContactTracking, APointInsideTheLumenWhereTheWalkLeavesItStaysThere) {
  const double r_wide = 0.0213, r_pleat = 0.0194, inside_m = 0.0015, nearer_m = 0.0002;
  const double d_wide = r_wide - inside_m, gap = d_wide + d_wide - nearer_m;  // centreline to centreline
  const Points q = hairpin(gap);
  Eigen::VectorXd radius(q.cols());
  for (int i = 0; i < q.cols(); ++i) radius(i) = q(1, i) > 0.5 * gap ? r_pleat : (q(1, i) > 0 ? 0.02 : r_wide);
  ColonModel colon = buildColonModelFromPoints(q, radius, 0.4, 1000, 20, Vec3::Zero(),
                                               std::make_shared<VoigtLaw>(28.9, 0.05));
  const WorldModel m = makeWorldModel(std::move(colon), ScopeParams(), ContactParams());
  ContactTracker tracker(m);
  tracker.updateCubics(makeColonState(m.colon, 0));
  EverySegment candidates;
  auto onWide = [&](const SplineLocation& at) { return m.colon.arclengthAt(at.j, at.p) < 0.2; };
  const Vec3 x(0.18, d_wide, 0);
  const SplineLocation on_wide{18, 0.0};  // x = 0.18 m
  // The pleat is the same part (the colon from the anchor round to it stays near x) and its
  // centreline is the nearer.
  SplineLocation scan;
  for (int j = 0; j + 1 < m.colon.n; ++j) considerSegment(tracker.cubics(), j, x, scan);
  ASSERT_FALSE(onWide(scan));
  ASSERT_NEAR(scan.d, d_wide - nearer_m, 1e-6);
  ASSERT_TRUE(colonStaysNear(tracker.cubics(), on_wide, scan, x, m.contact.self_neighbour_radii * r_wide));
  const SplineLocation at = tracker.nearestOnPart(m, x, on_wide, 0, candidates);
  EXPECT_TRUE(onWide(at));
  EXPECT_NEAR(clearance(m.colon, at), -inside_m, 1e-6);
  // Across from the wide part's axis towards the pleat's: on the wide part while inside its
  // lumen; beyond its wall, in the pleat's lumen, on the pleat (rule 2: a fold of the same
  // part), inside again.
  for (double y : {0.005, 0.015, 0.0198, 0.021, 0.025, 0.035}) {
    const SplineLocation here = tracker.nearestOnPart(m, Vec3(0.18, y, 0), on_wide, 0, candidates);
    EXPECT_EQ(onWide(here), y < r_wide) << "y = " << y;
    EXPECT_LT(clearance(m.colon, here), 0.0) << "y = " << y;
  }
}

// With every segment as a candidate and nothing ambiguous (a straight colon), the tracked
// narrowphase finds the paper's contacts, tracked or not.
TEST(ContactTracking, AgreesWithThePapersScanOnAStraightColon) {
  const WorldModel m = smallWorld(straightDown(0.9), 0.02);
  ContactTracker tracker(m);
  EverySegment candidates;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int contacts = 0;
  for (int trial = 0; trial < 6; ++trial) {
    WorldState s = makeWorldState(m);
    threadScopeAlongColon(m, s, 0.5 + 0.05 * trial);
    for (int k = 0; k < s.scope.inside; ++k) {
      s.scope.p_W[k] += 0.012 * test::randomVec3(u, rng);
      s.scope.R_WS[k] = expSO3(0.3 * test::randomVec3(u, rng)) * s.scope.R_WS[k];
    }
    WorldState scanned = s;
    std::vector<SegmentCubic> cubics;
    updateSegmentCubics(s.colon.q, cubics);
    scanWallContacts(m, cubics, scanned);
    tracker.updateCubics(s.colon);
    for (int round = 0; round < 2; ++round) {  // untracked, then with the first round's tracks
      tracker.trackWallContacts(m, s, candidates);
      std::map<std::pair<int, int>, const WallContact*> found;
      for (const WallContact& c : s.wall) found[{c.scope_segment, c.point}] = &c;
      ASSERT_EQ(s.wall.size(), scanned.wall.size());
      for (const WallContact& c : scanned.wall) {
        const WallContact* t = found[{c.scope_segment, c.point}];
        ASSERT_NE(t, nullptr);
        EXPECT_NEAR(t->depth_m, c.depth_m, 1e-12);
        EXPECT_LT((t->p_W_centre - c.p_W_centre).norm(), 1e-12);
      }
    }
    contacts += static_cast<int>(scanned.wall.size());
  }
  EXPECT_GT(contacts, 20);
}

}  // namespace
}  // namespace colosim
