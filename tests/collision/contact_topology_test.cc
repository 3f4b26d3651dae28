// The contact topology (core/contact_tracking.h) in the configuration where the scope used
// to pass through the wall (issue 16): a mobile loop of colon pressed against the part the
// scope came in by, the scope hooked in the loop and withdrawn. Every step is measured with
// core/lumen_check.h.
#include <algorithm>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "collision/contact_query.h"
#include "core/lumen_check.h"
#include "core/rotation.h"
#include "core/tension_law.h"
#include "fixture.h"
#include "trainer/assets.h"
#include "tests/core/every_segment.h"
#include "tests/random_vec3.h"
#include "step.h"

namespace colosim {
namespace {

// The shipped patient (assets/params/default.json) on a small anatomy written here, without
// gravity: an attached rectum straight up 14 cm; a free sigmoid that rises and turns
// anteriorly; its limb coming back down along the rectum's front, held there (attached
// lifters: where the withdrawal had pressed it in free_insertion), its wall pressed 4 mm
// into the rectum's; then forwards and left to an attached descending colon.
WorldModel foldedSigmoidWorld() {
  Parameters p = loadParameters(test::asset("params/default.json"));
  p.colon.gravity_m_per_s2 = 0;
  const double r_rectum = 0.02, r_sigmoid = 0.0175, y_limb = -(r_rectum + r_sigmoid - 0.004);
  Anatomy a;
  a.name = "folded_sigmoid";
  a.regions.push_back({"rectum", "attached", r_rectum, r_rectum, {{0, 0, 0}, {0, 0, 0.07}, {0, 0, 0.14}}});
  a.regions.push_back({"sigmoid", "free", r_sigmoid, r_sigmoid,
                       {{0, -0.002, 0.17}, {0, -0.015, 0.195}, {0, -0.04, 0.205}, {0, -0.062, 0.185},
                        {0, -0.05, 0.155}}});
  a.regions.push_back({"sigmoid_limb", "attached", r_sigmoid, r_sigmoid,
                       {{0, y_limb, 0.125}, {0, y_limb, 0.095}, {0, y_limb, 0.065},
                        {0.01, -0.05, 0.04}, {0.04, -0.075, 0.04}, {0.07, -0.08, 0.07}}});
  a.regions.push_back({"descending", "attached", r_sigmoid, r_sigmoid,
                       {{0.09, -0.07, 0.11}, {0.1, -0.05, 0.16}, {0.1, -0.04, 0.23}, {0.1, -0.04, 0.3}}});
  ColonModel colon = colonModelOf(a, "folded_sigmoid (contact_topology_test.cc)", p);
  return makeWorldModel(std::move(colon), p.scope, p.contact);
}

struct Worst {
  LumenCheck check;
  int exit_steps = 0;
  void add(const LumenCheck& c) {
    check.track_jump_m = std::max(check.track_jump_m, c.track_jump_m);
    check.wall_penetration_m = std::max(check.wall_penetration_m, c.wall_penetration_m);
    if (c.lumen_exit) ++exit_steps;
  }
};

// Rest arclength of a track [m].
double arclengthOf(const WorldModel& m, const WallTrack& t) { return m.colon.arclengthAt(t.colon_segment, t.p); }

// The configuration that tunnelled (free_insertion, hooked withdrawals): the scope threaded
// up the rectum, round the sigmoid and 6 cm down its limb; the withdrawal has pulled the
// scope in the limb 12 mm beyond the sigmoid's wall towards the rectum, where it lies inside
// the rectum's lumen, nearer the rectum's centreline than the sigmoid's. The sigmoid is the
// part the scope is in: every slice stays tracked on it, the wall pushes the scope back
// towards the sigmoid's axis, and held there the scope returns into the sigmoid. A rule that
// takes the nearer centreline, or lets a far part take over once a point is beyond its
// wall by more than a margin (1 cm), tracks those slices on the rectum: the scope has passed
// through the wall, and nothing pushes it back.
TEST(ContactTopology, AScopePulledThroughAFoldIntoTheRectumStaysInTheSigmoid) {
  const WorldModel m = foldedSigmoidWorld();
  double rectum_end_m = 0;  // rest arclength where the sigmoid begins
  for (int j = 0; j + 1 < m.colon.n; ++j)
    if (m.colon.region_names[m.colon.segment_region[j]] == "rectum") rectum_end_m = m.colon.s_rest_m(j + 1);
  int limb = 0;  // the limb's control point at z = 0.095 m
  while (!(std::abs(m.colon.q_rest(2, limb) - 0.095) < 0.008 && m.colon.q_rest(1, limb) < -0.02)) ++limb;
  const double depth_m = m.colon.s_rest_m(limb) + 0.03;
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, depth_m);
  // The segments in the limb (centre below z = 0.12 m, in front of the rectum) pulled
  // 0.0175 + 0.012 m towards the rectum (+y).
  const double shift_m = 0.0175 + 0.012;
  std::vector<int> pulled;
  for (int k = 0; k < s.scope.inside; ++k)
    if (s.scope.p_W[k].z() < 0.12 && s.scope.p_W[k].y() < -0.02) {
      s.scope.p_W[k].y() += shift_m;
      pulled.push_back(k);
    }
  ASSERT_GE(pulled.size(), 3u);
  FclContactQuery query(m);
  std::vector<double> arc;
  HandleInput in;
  in.insertion_m = depth_m;
  const int slices = m.scope.params.slices_per_segment;

  // The paper's nearest point takes the rectum for the pulled slices: a jump along the colon.
  {
    WorldState scanned = s;
    ScanContactQuery scan(m);
    scan.findWallContacts(m, scanned);
    EXPECT_LT(arclengthOf(m, scanned.slice_track[pulled.front() * slices]), rectum_end_m);
    EXPECT_GT(checkLumen(m, scanned, arc).track_jump_m, 0.1);
  }
  // The contact topology keeps them in the sigmoid, 12 mm beyond its wall, and its wall
  // pushes them back (-y, towards the sigmoid's axis).
  query.findWallContacts(m, s);
  for (int k : pulled) EXPECT_GT(arclengthOf(m, s.slice_track[k * slices]), rectum_end_m) << "segment " << k;
  LumenCheck c = checkLumen(m, s, arc);
  EXPECT_TRUE(c.lumen_exit);
  EXPECT_GT(c.wall_penetration_m, 0.01);
  EXPECT_LT(c.track_jump_m, 0.03);
  Vec3 push = Vec3::Zero();
  for (const WallContact& w : s.wall)
    if (w.scope_segment == 0) push -= w.normal_W * w.depth_m;
  EXPECT_LT(push.y(), -0.01);
  // Held at the handle, the scope returns into the sigmoid within 0.3 s, never tracked
  // elsewhere.
  Worst held;
  for (int step = 0; step < 300; ++step) {
    stepWorld(m, s, in, query, kDt);
    for (int k : pulled)
      ASSERT_GT(arclengthOf(m, s.slice_track[k * slices]), rectum_end_m) << "step " << step << ", segment " << k;
    if (step >= 200) held.add(checkLumen(m, s, arc));
  }
  EXPECT_EQ(held.exit_steps, 0);
  EXPECT_LT(held.check.wall_penetration_m, 0.005);
  EXPECT_LT(held.check.track_jump_m, 0.03);
}


// EverySegment, counting what it offers.
struct CountingEverySegment final : TrackingCandidates {
  SplineLocation nearestOther(const std::vector<SegmentCubic>& cubics, const ColonModel& colon, const Vec3& x, int k,
                              const SplineLocation& local, double local_clearance_m) override {
    const SplineLocation other = every.nearestOther(cubics, colon, x, k, local, local_clearance_m);
    ++queries;
    if (other.j >= 0) ++offered;
    return other;
  }
  EverySegment every;
  int queries = 0, offered = 0;
};

// The fast path and brute force: the broadphase's candidate search (the least clearance,
// pruned by lower bounds) finds what a search of every colon segment finds, bit for bit,
// in the folded sigmoid with the scope shaken about it (the colon too; 80 poses) and tracked twice
// (the second round from the first's tracks).
TEST(ContactTopology, TheBroadphaseFindsWhatASearchOfEverySegmentFinds) {
  const WorldModel m = foldedSigmoidWorld();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  FclContactQuery query(m);
  ContactTracker tracker(m);
  CountingEverySegment every;
  int contacts = 0;
  for (int trial = 0; trial < 80; ++trial) {
    WorldState fast = makeWorldState(m);
    threadScopeAlongColon(m, fast, 0.15 + 0.005 * trial);
    for (int k = 0; k < fast.scope.inside; ++k) {
      fast.scope.p_W[k] += 0.010 * test::randomVec3(u, rng);
      fast.scope.R_WS[k] = expSO3(0.3 * test::randomVec3(u, rng)) * fast.scope.R_WS[k];
    }
    for (int i = 0; i < m.colon.n; ++i) fast.colon.q.col(i) += 0.006 * test::randomVec3(u, rng);
    WorldState brute = fast;
    for (int round = 0; round < 2; ++round) {
      query.findWallContacts(m, fast);
      tracker.updateCubics(brute.colon);
      tracker.trackWallContacts(m, brute, every);
      ASSERT_EQ(fast.slice_track.size(), brute.slice_track.size());
      for (size_t t = 0; t < fast.slice_track.size(); ++t) {
        EXPECT_EQ(fast.slice_track[t].colon_segment, brute.slice_track[t].colon_segment) << "trial " << trial << " slice " << t;
        EXPECT_EQ(fast.slice_track[t].p, brute.slice_track[t].p) << "trial " << trial << " slice " << t;
      }
      for (size_t t = 0; t < fast.track.size(); ++t) {
        EXPECT_EQ(fast.track[t].colon_segment, brute.track[t].colon_segment) << "trial " << trial << " point " << t;
        EXPECT_EQ(fast.track[t].p, brute.track[t].p) << "trial " << trial << " point " << t;
      }
      ASSERT_EQ(fast.wall.size(), brute.wall.size()) << "trial " << trial;
      for (size_t c = 0; c < fast.wall.size(); ++c) EXPECT_EQ(fast.wall[c].depth_m, brute.wall[c].depth_m);
      contacts += static_cast<int>(fast.wall.size());
    }
  }
  std::printf("%d wall contacts compared; the search offered %d of %d queries a location off the walk\n", contacts,
              every.offered, every.queries);
  EXPECT_GT(contacts, 200);
  EXPECT_GT(every.offered, 20);  // the comparison covers the candidate search, not only the walk
}

}  // namespace
}  // namespace colosim
