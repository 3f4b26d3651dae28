#include "core/contact_tracking.h"

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "core/rotation.h"
#include "core/tension_law.h"
#include "tests/random_vec3.h"

namespace colosim {
namespace {

// A candidate search without a broadphase: every colon segment off the walked stretch.
class EverySegment final : public TrackingCandidates {
 public:
  SplineLocation nearestOther(const std::vector<SegmentCubic>& cubics, const Vec3& x, int,
                              const SplineLocation& local) override {
    SplineLocation other;
    for (int j = 0; j < static_cast<int>(cubics.size()); ++j)
      if (local.j < 0 || std::abs(j - local.j) > 1) considerSegment(cubics, j, x, other);
    return other;
  }
};

WorldModel worldFromPoints(const Points& q, double radius_m) {
  ColonModel colon = buildColonModelFromPoints(q, Eigen::VectorXd::Constant(q.cols(), radius_m), 0.4, 1000, 20,
                                               Vec3::Zero(), std::make_shared<VoigtLaw>(28.9, 0.05));
  return makeWorldModel(std::move(colon), ScopeParams(), ContactParams());
}

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

Points straight(double length_m) {
  const int n = static_cast<int>(std::lround(length_m / 0.015)) + 1;
  Points q(3, n);
  for (int i = 0; i < n; ++i) q.col(i) = Vec3(0, 0, -0.015 * i);
  return q;
}

TEST(ContactTracking, WalkReachesTheLocalMinimumAlongTheSpline) {
  const WorldModel m = worldFromPoints(straight(0.6), 0.02);
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

// A point tracked on part A of a hairpin, 6-8 mm outside A's wall and inside B's lumen:
// rule 3 keeps it on A while it is within A's radius plus the margin (1 cm), and lets B
// take over beyond. Untracked, it takes the nearest part, B.
TEST(ContactTracking, AFarPartTakesOverOnlyBeyondTheTrackedLumensReach) {
  const double r = 0.02, gap = 0.05;
  const WorldModel m = worldFromPoints(hairpin(gap), r);
  ContactTracker tracker(m);
  const ColonState rest = makeColonState(m.colon, 0);
  tracker.updateCubics(rest);
  EverySegment candidates;
  auto partAt = [&](const SplineLocation& at) { return m.colon.arclengthAt(at.j, at.p) < 0.2 ? 'A' : 'B'; };
  const int on_a = 10;  // x = 0.1 m
  const Vec3 within(0.1, 0.028, 0), beyond(0.1, 0.031, 0);
  EXPECT_EQ(partAt(tracker.nearestTracked(m, within, on_a, 0, candidates)), 'A');
  EXPECT_EQ(partAt(tracker.nearestTracked(m, beyond, on_a, 0, candidates)), 'B');
  EXPECT_EQ(partAt(tracker.nearestTracked(m, within, -1, 0, candidates)), 'B');
}

TEST(ContactTracking, ANearerLocationCloseAlongTheColonAlwaysTakesOver) {
  const WorldModel m = worldFromPoints(straight(0.6), 0.02);
  const SplineLocation local{10, 0.5, 0.05}, other{13, 0.5, 0.01};  // 4.5 cm apart: < pi radii
  const SplineLocation kept = keepTrackedPart(m, local, other);
  EXPECT_EQ(kept.j, 13);
}

// With every segment as a candidate and nothing ambiguous (a straight colon), the tracked
// narrowphase finds the paper's contacts, tracked or not.
TEST(ContactTracking, AgreesWithThePapersScanOnAStraightColon) {
  const WorldModel m = worldFromPoints(straight(0.9), 0.02);
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
