#include "collision/contact_query.h"

#include <map>
#include <random>

#include <gtest/gtest.h>

#include "core/colon_step.h"
#include "core/rotation.h"
#include "core/scope_step.h"
#include "fixture.h"
#include "trainer/assets.h"
#include "tests/random_vec3.h"
#include "step.h"

namespace colosim {
namespace {

WorldModel adultWorld() {
  const Parameters p = loadParameters(test::asset("params/default.json"));
  return loadWorldModel(test::asset("anatomy/adult.json"), p);
}

// A world around a colon given by its control points (uniform radius and mesentery).
WorldModel worldFromPoints(const Points& q, double radius, double k, double c, const Vec3& g,
                           double mu = 0.1) {
  ColonModel colon = buildColonModelFromPoints(q, Eigen::VectorXd::Constant(q.cols(), radius), 0.4, k, c, g,
                                               std::make_shared<VoigtLaw>(28.9, 0.05));
  ScopeParams sp;
  ContactParams cp;
  cp.friction_coefficient = mu;
  return makeWorldModel(std::move(colon), sp, cp);
}

// Random scope poses in the adult colon: threaded to a random depth, then every segment
// displaced sideways and turned, so that some interaction points lie outside the lumen.
void randomPose(const WorldModel& m, WorldState& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> depth(0.2, 1.5), u(-1, 1);
  const double turn_rad = 3 * u(rng);  // drawn first, then the depth: the same poses with every compiler
  const double depth_m = depth(rng);
  threadScopeAlongColon(m, s, depth_m, turn_rad);
  for (int k = 0; k < s.scope.inside; ++k) {
    s.scope.p_W[k] += 0.012 * test::randomVec3(u, rng);
    s.scope.R_WS[k] = expSO3(0.3 * test::randomVec3(u, rng)) * s.scope.R_WS[k];
  }
}

// Whether the nearest wall location of x is unambiguous: no part of the colon far in
// arclength (another part of a loop) comes within `gap` of the least clearance (distance
// less the lumen radius, each segment at its point nearest x).
bool unambiguous(const WorldModel& m, const WorldState& s, const Vec3& x, double gap) {
  auto clearanceOf = [&](int j, const ClosestPoint& c) { return c.distance - m.colon.radiusAt(j, c.p); };
  int best_j = 0;
  ClosestPoint best = closestPointOnSegment(s.colon.q, 0, x);
  for (int j = 1; j + 1 < m.colon.n; ++j) {
    const ClosestPoint c = closestPointOnSegment(s.colon.q, j, x);
    if (clearanceOf(j, c) < clearanceOf(best_j, best)) best = c, best_j = j;
  }
  const double s_best = m.colon.arclengthAt(best_j, best.p);
  for (int j = 0; j + 1 < m.colon.n; ++j) {
    const ClosestPoint c = closestPointOnSegment(s.colon.q, j, x);
    const double ds = std::abs(m.colon.arclengthAt(j, c.p) - s_best);
    if (ds > 0.1 && clearanceOf(j, c) < clearanceOf(best_j, best) + gap) return false;
  }
  return true;
}

TEST(ContactQuery, FclAndThePapersScanAgreeWhereTheNearestWallIsUnambiguous) {
  const WorldModel m = adultWorld();
  std::mt19937 rng(21);
  FclContactQuery fcl(m);
  ScanContactQuery scan(m);
  int compared = 0, poses = 0;
  for (int trial = 0; trial < 12; ++trial) {
    WorldState s = makeWorldState(m);
    randomPose(m, s, rng);
    WorldState a = s, b = s;
    // Twice with FCL: once untracked, once with the tracks of the first query.
    for (int round = 0; round < 2; ++round) {
      fcl.findWallContacts(m, a);
      scan.findWallContacts(m, b);
      std::map<std::pair<int, int>, WallContact> by_point;
      for (const WallContact& c : b.wall) by_point[{c.scope_segment, c.point}] = c;
      std::map<std::pair<int, int>, WallContact> fcl_points;
      for (const WallContact& c : a.wall) fcl_points[{c.scope_segment, c.point}] = c;
      for (int k = 0; k < s.scope.inside; ++k) {
        for (int i = 0; i < static_cast<int>(m.scope.interaction_points_S.size()); ++i) {
          const Vec3 x = interactionPoint(m.scope, s.scope, k, i);
          if (!unambiguous(m, s, x, 0.002)) continue;
          const auto f = fcl_points.find({k, i}), g = by_point.find({k, i});
          ASSERT_EQ(f != fcl_points.end(), g != by_point.end()) << "segment " << k << " point " << i;
          if (f == fcl_points.end()) continue;
          ++compared;
          EXPECT_NEAR(f->second.depth_m, g->second.depth_m, 1e-12);
          EXPECT_LT((f->second.normal_W - g->second.normal_W).norm(), 1e-9);
          EXPECT_NEAR(m.colon.arclengthAt(f->second.colon_segment, f->second.p),
                      m.colon.arclengthAt(g->second.colon_segment, g->second.p), 1e-9);
        }
      }
    }
    // The forces of both contact sets agree too.
    std::vector<SplineLoad> ca, cb;
    std::vector<ScopeLoad> sa, sb;
    applyWallContacts(m.contact, m.colon, a.colon, m.scope, a.scope, a.wall, ca, sa);
    applyWallContacts(m.contact, m.colon, b.colon, m.scope, b.scope, b.wall, cb, sb);
    Vec3 fa = Vec3::Zero(), fb = Vec3::Zero();
    for (const ScopeLoad& l : sa) fa += l.force_N;
    for (const ScopeLoad& l : sb) fb += l.force_N;
    if (a.wall.size() == b.wall.size()) {
      EXPECT_LT((fa - fb).norm(), 1e-9 * (1 + fa.norm()));
      ++poses;
    }
  }
  EXPECT_GT(compared, 200);  // the poses really touched the wall
  EXPECT_GT(poses, 6);
}

// A hairpin colon: part A along +x at y = 0, a U-turn, part B back along -x at
// y = 2 r - 4 mm (the two walls pressed together, as in a sigmoid loop).
Points hairpin(double r) {
  std::vector<Vec3> pts;
  const double sep = 2 * r - 0.004, turn = 0.5 * sep;
  for (double x = 0; x <= 0.20 + 1e-9; x += 0.015) pts.emplace_back(x, 0, 0);
  for (int i = 1; i < 8; ++i) {
    const double a = M_PI * i / 8;
    pts.emplace_back(0.20 + turn * std::sin(a), turn * (1 - std::cos(a)), 0);
  }
  for (double x = 0.20; x >= -0.0001; x -= 0.015) pts.emplace_back(x, sep, 0);
  Points q(3, static_cast<int>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) q.col(static_cast<int>(i)) = pts[i];
  return q;
}

// The scope threaded 12 cm into part A of the hairpin, its tip segment (0) at x = 0.1 m
// pressed towards part B: its top interaction point is 2 mm beyond A's wall, hence 2 mm
// inside B's lumen.
void pressTipTowardsPartB(const WorldModel& m, WorldState& s, double r) {
  threadScopeAlongColon(m, s, 0.12);
  s.scope.R_WS[0].col(0) = Vec3(0, 1, 0);
  s.scope.R_WS[0].col(1) = Vec3(0, 0, 1);
  s.scope.R_WS[0].col(2) = Vec3(1, 0, 0);
  const Vec3 top_S = m.scope.interaction_points_S[0];  // (r_scope, 0, h/2): along d1 = +y
  s.scope.p_W[0] = Vec3(0.1, r + 0.002 - top_S.x(), 0) - s.scope.R_WS[0] * Vec3(0, 0, top_S.z());
  ASSERT_NEAR(interactionPoint(m.scope, s.scope, 0, 0).y(), r + 0.002, 1e-12);
}

// That top point touches part A's wall, 2 mm deep, pushed back towards A's axis.
void expectTopPointOnPartAsWall(const WorldModel& m, const WorldState& s) {
  bool found = false;
  for (const WallContact& c : s.wall) {
    if (c.scope_segment != 0 || c.point != 0) continue;
    found = true;
    EXPECT_LT(m.colon.arclengthAt(c.colon_segment, c.p), 0.2);  // part A
    EXPECT_NEAR(c.depth_m, 0.002, 1e-6);
    EXPECT_GT(c.normal_W.y(), 0.99);
  }
  EXPECT_TRUE(found);
}

TEST(ContactQuery, RobustQueryStaysOnTheTrackedPartOfALoop) {
  const double r = 0.017;
  const WorldModel m = worldFromPoints(hairpin(r), r, 1000, 20, Vec3::Zero());
  WorldState s = makeWorldState(m);
  const int k = 0;
  pressTipTowardsPartB(m, s, r);

  // The paper's scan snaps to part B (the nearer centreline) and sees no contact.
  WorldState scan_state = s;
  ScanContactQuery scan(m);
  scan.findWallContacts(m, scan_state);
  const WallTrack snapped = scan_state.track[0];
  EXPECT_GT(m.colon.arclengthAt(snapped.colon_segment, snapped.p), 0.25);  // part B
  for (const WallContact& c : scan_state.wall) EXPECT_FALSE(c.scope_segment == k && c.point == 0);

  // The robust query follows the scope from the anus along part A, keeps the point in A
  // and pushes it back.
  FclContactQuery fcl(m);
  fcl.findWallContacts(m, s);
  expectTopPointOnPartAsWall(m, s);
}

// Tracks are a function of the configuration: a segment whose tracks were carried to part
// B of the hairpin while the scope lies in part A is found in A again, and the point pressed
// 2 mm beyond A's wall touches it; kept in B the point would be inside B's lumen and the
// wall pushing the scope back would be missing (docs/hardening.md, "Contact tracking").
TEST(ContactQuery, TracksCarriedToAnotherPartComeBackToTheScopesPath) {
  const double r = 0.017;
  const WorldModel m = worldFromPoints(hairpin(r), r, 1000, 20, Vec3::Zero());
  WorldState s = makeWorldState(m);
  const int k = 0;
  pressTipTowardsPartB(m, s, r);
  FclContactQuery fcl(m);
  fcl.findWallContacts(m, s);  // every segment tracked where it lies, in part A
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  auto tracked_at_m = [&](int t) { return m.colon.arclengthAt(s.track[t].colon_segment, s.track[t].p); };
  for (int i = 0; i < P; ++i) ASSERT_LT(tracked_at_m(k * P + i), 0.2);
  ASSERT_LT(tracked_at_m((k + 1) * P), 0.2);

  // Segment k's tracks carried to part B, opposite x = 0.1 m.
  int b_segment = -1;
  for (int j = 0; j + 1 < m.colon.n; ++j)
    if (m.colon.s_rest_m(j) > 0.25 && std::abs(s.colon.q(0, j) - 0.1) < 0.008) b_segment = j;
  ASSERT_GE(b_segment, 0);
  for (int i = 0; i < P; ++i) s.track[k * P + i] = {b_segment, 0.5};
  fcl.findWallContacts(m, s);
  expectTopPointOnPartAsWall(m, s);
  for (int i = 0; i < P; ++i) EXPECT_LT(tracked_at_m(k * P + i), 0.2);
}

TEST(ContactForces, ActionEqualsReaction) {
  const WorldModel m = adultWorld();
  std::mt19937 rng(5);
  WorldState s = makeWorldState(m);
  randomPose(m, s, rng);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (int k = 0; k < s.scope.inside; ++k) s.scope.v_W[k] = test::randomVec3(u, rng);
  for (int i = 0; i < m.colon.n; ++i) s.colon.v.col(i) = test::randomVec3(u, rng);
  FclContactQuery q(m);
  q.findWallContacts(m, s);
  ASSERT_GT(s.wall.size(), 10u);
  std::vector<SplineLoad> colon_loads;
  std::vector<ScopeLoad> scope_loads;
  applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, s.wall, colon_loads, scope_loads);
  Vec3 total = Vec3::Zero(), scope_total = Vec3::Zero();
  for (const ScopeLoad& l : scope_loads) total += l.force_N, scope_total += l.force_N;
  // The colon side as the control points receive it, through the blending functions.
  for (const SplineLoad& l : colon_loads) {
    const Blend b = blend(m.colon.n, l.segment, l.p, 0);
    for (int a = 0; a < 4; ++a) total += b.w[a] * l.force_N;
  }
  EXPECT_GT(scope_total.norm(), 0.1);
  EXPECT_LT(total.norm(), 1e-12 * scope_total.norm() + 1e-14);
}

// A contact `depth_m` deep along +z at colon location 5 / 0.5, of interaction point 0 of
// scope segment 2 or (face) of the tip face's lens, the scope threaded to 0.2 m.
WallContact pressedPoint(const WorldModel& m, const WorldState& s, bool face, double depth_m) {
  WallContact c;
  c.scope_segment = face ? 0 : 2;
  c.point = face ? static_cast<int>(m.scope.interaction_points_S.size()) : 0;
  c.p_W_point = face ? tipFacePoint(m.scope, s.scope, 0) : interactionPoint(m.scope, s.scope, 2, 0);
  c.colon_segment = 5;
  c.p = 0.5;
  c.normal_W = Vec3(0, 0, 1);
  c.depth_m = depth_m;
  return c;
}

// The normal force of that contact on the adult colon with parameters q.
double pressedPointForce(const Parameters& q, bool face, double depth_m) {
  const WorldModel m = loadWorldModel(test::asset("anatomy/adult.json"), q);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.2);
  std::vector<WallContact> contacts = {pressedPoint(m, s, face, depth_m)};
  std::vector<SplineLoad> colon_loads;
  std::vector<ScopeLoad> scope_loads;
  applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, contacts, colon_loads, scope_loads);
  return contacts[0].normal_force_N;
}

// The contact's coupling (ContactParams::coupling_predictor): each body's load carries the
// other body's move over the step at its start velocity. A wall receding from a pressed point
// at 0.5 m/s along the normal lowers the scope's normal load by k dt v; the point advancing
// at 0.2 m/s raises the colon's by k dt v; the tangential parts stay; and a move that would
// take the contact apart leaves no pull (the normal load stops at zero).
TEST(ContactForces, ThePredictorCarriesTheOtherBodysMoveOverTheStep) {
  const Parameters p = loadParameters(test::asset("params/default.json"));
  const WorldModel m = loadWorldModel(test::asset("anatomy/adult.json"), p);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.2);
  const double d = 0.002, dt = 0.001, k = p.contact.wall_stiffness_N_per_m;
  auto loads = [&](double wall_speed, double point_speed, double step_s, Vec3* scope_force, Vec3* colon_force) {
    WorldState t = s;
    std::vector<WallContact> contacts = {pressedPoint(m, t, false, d)};
    t.colon.v.colwise() = Vec3(0, 0, wall_speed);
    t.scope.v_W[2] = Vec3(0, 0, point_speed);
    t.scope.w_W[2].setZero();
    std::vector<SplineLoad> colon_loads;
    std::vector<ScopeLoad> scope_loads;
    applyWallContacts(m.contact, m.colon, t.colon, m.scope, t.scope, contacts, colon_loads, scope_loads, nullptr, step_s);
    *scope_force = scope_loads.at(0).force_N;
    *colon_force = colon_loads.at(0).force_N;
  };
  Vec3 held_scope, held_colon, scope, colon;
  loads(0.5, 0.2, 0.0, &held_scope, &held_colon);
  loads(0.5, 0.2, dt, &scope, &colon);
  // The whole colon moves alike, so the wall point moves at 0.5 m/s along the normal
  // (0, 0, 1), away from the point.
  EXPECT_NEAR(scope.z() - held_scope.z(), k * dt * 0.5, 1e-9);  // the scope pushed back less
  EXPECT_NEAR(colon.z() - held_colon.z(), k * dt * 0.2, 1e-9);  // the colon pushed out more
  EXPECT_NEAR((scope - held_scope).head<2>().norm(), 0.0, 1e-12);
  EXPECT_NEAR((colon - held_colon).head<2>().norm(), 0.0, 1e-12);
  // Receding at 1.5 m/s: the force is 2 N less 1.5 N of damping, and the wall's move over
  // the step would take 1.5 N more: no pull on the scope.
  ASSERT_EQ(p.contact.wall_damping_Ns_per_m, 1.0);
  loads(1.5, 0.0, dt, &scope, &colon);
  EXPECT_NEAR(scope.z(), 0.0, 1e-9);
  EXPECT_GT(colon.z(), 0.0);
}

// ... limited where both bodies are light against their contacts (the limit given): with
// a = K_sum dt^2 / m_eff on each side (the summed stiffness on the scope segment and on the
// contact's nearest control point), the prediction is scaled by 1 / (a_scope a_colon) when
// that product exceeds 1. One point pressed 2 mm deep (1000 N/m on a 3 g segment and a 6 g
// control point) keeps the whole prediction. Twenty points pressed 4 mm deep at the same place,
// through the wall's thickness (31,000 N/m each, 34 N: below the force limit), keep a small
// part of it, and forty keep a quarter of what twenty keep: a_scope a_colon grows as the
// square of the summed stiffness.
TEST(ContactForces, ThePredictionIsLimitedWhereBothBodiesAreLightAgainstTheirContacts) {
  const Parameters p = loadParameters(test::asset("params/default.json"));
  const WorldModel m = loadWorldModel(test::asset("anatomy/adult.json"), p);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.2);
  s.colon.v.colwise() = Vec3(0, 0, 0.5);  // the wall recedes at 0.5 m/s along the normal
  const double dt = 0.001;
  // The scope's normal load with the prediction less that without, per contact [N].
  auto predicted = [&](int count, double depth_m, CouplingStiffness* limit) {
    std::vector<WallContact> contacts(count, pressedPoint(m, s, false, depth_m));
    std::vector<SplineLoad> colon_loads;
    std::vector<ScopeLoad> scope_loads;
    applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, contacts, colon_loads, scope_loads, nullptr, dt,
                      nullptr, limit);
    const double with = scope_loads.at(0).force_N.z();
    scope_loads.clear();
    applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, contacts, colon_loads, scope_loads);
    return with - scope_loads.at(0).force_N.z();
  };
  CouplingStiffness limit;
  limit.scope_segment_N_per_m.setZero(m.scope.segment_count);
  limit.colon_point_N_per_m.setZero(m.colon.n);
  const double k = p.contact.wall_stiffness_N_per_m, k_deep = k + p.contact.wall_backing_stiffness_N_per_m;
  EXPECT_NEAR(predicted(1, 0.002, &limit), k * dt * 0.5, 1e-9);
  EXPECT_NEAR(predicted(1, 0.002, nullptr), k * dt * 0.5, 1e-9);
  EXPECT_NEAR(predicted(20, 0.004, nullptr), k_deep * dt * 0.5, 1e-9);
  const double twenty = predicted(20, 0.004, &limit);
  EXPECT_NEAR(limit.scope_segment_N_per_m(2), 20 * k_deep, 1e-6);
  EXPECT_GT(twenty, 0.0);
  EXPECT_LT(twenty, 1e-3 * k_deep * dt * 0.5);
  EXPECT_NEAR(predicted(40, 0.004, &limit), twenty / 4, 1e-12);  // a difference of two 34 N loads
}

// The wall is stiff per length of scope, not per interaction point: the same depth on a
// slice half as long (segments of 0.75 cm) gives half the force per point, so that the
// wall's force per metre of scope pressed into it does not change with the resolution.
// The tip face's points are not on a slice and keep the per-point values; with the
// reference length 0 (the paper's eq. 7) every point keeps them.
TEST(ContactForces, WallStiffnessIsPerLengthOfScope) {
  const Parameters p = loadParameters(test::asset("params/default.json"));
  auto pointForce = [&](double segment_m, double reference_m, bool face, double depth_m) {
    Parameters q = p;
    q.scope.segment_length_m = segment_m;
    q.contact.wall_reference_slice_m = reference_m;
    return pressedPointForce(q, face, depth_m);
  };
  const double d = 0.002;  // 2 N at 1000 N/m: well below the limit
  const double coarse = pointForce(0.015, 0.015, false, d), fine = pointForce(0.0075, 0.015, false, d);
  EXPECT_NEAR(coarse, p.contact.wall_stiffness_N_per_m * d, 1e-9);
  EXPECT_NEAR(fine, 0.5 * coarse, 1e-9);  // two points per 1.5 cm of scope: the same force per length
  EXPECT_NEAR(pointForce(0.0075, 0.015, true, d), pointForce(0.015, 0.015, true, d), 1e-9);
  EXPECT_NEAR(pointForce(0.0075, 0.0, false, d), coarse, 1e-9);
  // The limit scales with the slice too: at 3x the limit's depth, a half slice gives half of it.
  const double deep = 3 * p.contact.max_point_force_N / p.contact.wall_stiffness_N_per_m;
  EXPECT_NEAR(pointForce(0.0075, 0.015, false, deep), 0.5 * p.contact.max_point_force_N, 1e-9);
}

// ... and per area: twice the points round a slice give each half the force, so that a slice
// pressed all round carries the same whatever its sampling; the limit with it; the tip
// face's points and a reference count of 0 (the paper's eq. 7) keep the per-point values.
TEST(ContactForces, WallStiffnessIsPerAreaOfScope) {
  const Parameters p = loadParameters(test::asset("params/default.json"));
  ASSERT_EQ(p.scope.points_per_slice, p.contact.wall_reference_points_per_slice);
  auto pointForce = [&](int points, int reference, bool face, double depth_m) {
    Parameters q = p;
    q.scope.points_per_slice = points;
    q.contact.wall_reference_points_per_slice = reference;
    return pressedPointForce(q, face, depth_m);
  };
  const double d = 0.002;  // within the wall's thickness, well below the limit
  const double six = pointForce(6, 6, false, d);
  EXPECT_NEAR(six, p.contact.wall_stiffness_N_per_m * d, 1e-9);
  EXPECT_NEAR(pointForce(12, 6, false, d), 0.5 * six, 1e-9);
  EXPECT_NEAR(pointForce(12, 6, true, d), pointForce(6, 6, true, d), 1e-9);
  EXPECT_NEAR(pointForce(12, 0, false, d), six, 1e-9);
  const double deep = 3 * p.contact.max_point_force_N / p.contact.wall_stiffness_N_per_m;
  EXPECT_NEAR(pointForce(12, 6, false, deep), 0.5 * p.contact.max_point_force_N, 1e-9);
}

// The wall bottoms out (ContactParams::wall_thickness_m): within the wall's thickness the
// normal force is the paper's k d; beyond it the backing adds k_b (d - t), and the
// stiffness handed to the implicit solves is k + k_b, continuous in force at d = t. With
// k_b = 0 the wall is linear at every depth.
TEST(ContactForces, TheWallBottomsOutBeyondItsThickness) {
  WorldModel m = adultWorld();
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.2);
  const ContactParams& P = m.contact;
  ASSERT_GT(P.wall_backing_stiffness_N_per_m, 0);
  auto load = [&](double depth_m) {
    std::vector<WallContact> contacts = {pressedPoint(m, s, false, depth_m)};
    std::vector<SplineLoad> colon_loads;
    std::vector<ScopeLoad> scope_loads;
    applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, contacts, colon_loads, scope_loads);
    return scope_loads.at(0);
  };
  const double k = P.wall_stiffness_N_per_m, kb = P.wall_backing_stiffness_N_per_m, t = P.wall_thickness_m;
  for (double d : {0.5 * t, 0.99 * t}) {
    const ScopeLoad l = load(d);
    EXPECT_NEAR(-l.force_N.z(), k * d, 1e-9) << d;
    EXPECT_NEAR(l.stiffness_N_per_m(2, 2), k, 1e-9) << d;
  }
  const double deep = t + 0.0005;
  ASSERT_LT(k * deep + kb * (deep - t), P.max_point_force_N);  // below the force limit
  const ScopeLoad l = load(deep);
  EXPECT_NEAR(-l.force_N.z(), k * deep + kb * (deep - t), 1e-9);
  EXPECT_NEAR(l.stiffness_N_per_m(2, 2), k + kb, 1e-9);
  EXPECT_NEAR(-load(t + 1e-9).force_N.z(), k * t, 1e-4);  // continuous at the thickness
  m.contact.wall_backing_stiffness_N_per_m = 0;
  EXPECT_NEAR(-load(deep).force_N.z(), k * deep, 1e-9);
}

// The contact force limit (docs/hardening.md): a point pushed far into the wall asks for
// more than max_point_force_N; it gets exactly the limit, in the same direction, with its
// stiffness and damping scaled alike, and the report counts it. NaN geometry is dropped.
TEST(ContactForces, ForceAboveTheLimitIsScaledDownAndCounted) {
  WorldModel m = adultWorld();
  m.contact.wall_backing_stiffness_N_per_m = 0;  // the linear wall: depths in proportion to forces
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.2);
  const double limit = m.contact.max_point_force_N;
  WallContact c = pressedPoint(m, s, false, 3.0 * limit / m.contact.wall_stiffness_N_per_m);  // asks ~3 x the limit
  WallContact bad = c;
  bad.depth_m = std::nan("");
  std::vector<WallContact> contacts = {c, bad};
  std::vector<SplineLoad> colon_loads;
  std::vector<ScopeLoad> scope_loads;
  ContactLimitReport rep;
  const double max_force =
      applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, contacts, colon_loads, scope_loads, &rep);
  EXPECT_EQ(rep.limited, 1);
  EXPECT_EQ(rep.non_finite, 1);
  EXPECT_NEAR(rep.asked_N, 3.0 * limit, 1e-6 * limit);
  EXPECT_NEAR(max_force, limit, 1e-9 * limit);
  ASSERT_EQ(scope_loads.size(), 1u);
  ASSERT_EQ(colon_loads.size(), 1u);
  EXPECT_NEAR(scope_loads[0].force_N.norm(), limit, 1e-9 * limit);
  EXPECT_LT(scope_loads[0].force_N.dot(c.normal_W), 0);  // still pushing the point back in
  EXPECT_NEAR(scope_loads[0].stiffness_N_per_m(2, 2), m.contact.wall_stiffness_N_per_m / 3.0,
              1e-6 * m.contact.wall_stiffness_N_per_m);
  EXPECT_TRUE((colon_loads[0].force_N + scope_loads[0].force_N).norm() < 1e-12);
  // The report says which contact it limited: kind, place, depth and closing speed (the
  // scope at rest: 0).
  EXPECT_EQ(rep.worst.kind, ContactLimitReport::Worst::Kind::kSlicePoint);
  EXPECT_NEAR(rep.worst.asked_N, 3.0 * limit, 1e-6 * limit);
  EXPECT_EQ(rep.worst.colon_segment, c.colon_segment);
  EXPECT_EQ(rep.worst.p, c.p);
  EXPECT_EQ(rep.worst.depth_m, c.depth_m);
  EXPECT_EQ(rep.worst.closing_m_per_s, 0.0);
  // A report merged into another keeps the larger worst contact and adds the counts.
  ContactLimitReport total;
  total.limited = 2;
  total.worst.asked_N = 2.0 * limit;
  total.merge(rep);
  EXPECT_EQ(total.limited, 3);
  EXPECT_EQ(total.non_finite, 1);
  EXPECT_EQ(total.worst.asked_N, rep.worst.asked_N);
  // Below the limit nothing changes.
  contacts = {c};
  contacts[0].depth_m = 0.5 * limit / m.contact.wall_stiffness_N_per_m;
  colon_loads.clear();
  scope_loads.clear();
  applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, contacts, colon_loads, scope_loads, &rep);
  EXPECT_EQ(rep.limited, 0);
  EXPECT_NEAR(scope_loads[0].force_N.norm(), 0.5 * limit, 1e-9 * limit);
}

TEST(ContactQuery, NeighbourSpheresNeverRepel) {
  const WorldModel m = adultWorld();
  WorldState s = makeWorldState(m);
  FclContactQuery fcl(m);
  ScanContactQuery scan(m);
  fcl.findSelfContacts(m, s);
  EXPECT_TRUE(s.self.empty());  // the rest shape has overlapping neighbours only
  scan.findSelfContacts(m, s);
  EXPECT_TRUE(s.self.empty());
  // Neighbours overlap heavily (1.5 cm spacing, ~2 cm radius) but are excluded.
  EXPECT_LT((m.colon.q_rest.col(1) - m.colon.q_rest.col(0)).norm(), m.colon.radius_m(0) + m.colon.radius_m(1));
  EXPECT_TRUE(selfNeighbours(m.contact, m.colon, 0, 1));
  EXPECT_TRUE(selfNeighbours(m.contact, m.colon, 10, 13));
  EXPECT_FALSE(selfNeighbours(m.contact, m.colon, 10, 20));
}

TEST(SelfCollision, CrossingPartsOfALoopSeparate) {
  // Two straight parts joined by a long free arc, starting interpenetrated by 1 cm.
  const double r = 0.017;
  std::vector<Vec3> pts;
  for (int i = 0; i < 12; ++i) pts.emplace_back(0.015 * i, 0, 0);
  for (int i = 1; i < 20; ++i) {
    const double a = M_PI * i / 20;
    pts.emplace_back(0.165 + 0.1 * std::sin(a), 0.1 * (1 - std::cos(a)), 0.0);
  }
  for (int i = 0; i < 12; ++i) pts.emplace_back(0.165 - 0.015 * i, 0.2 - 0.1 - 0.1 + 2 * r - 0.01, 0.0);
  Points q(3, static_cast<int>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) q.col(static_cast<int>(i)) = pts[i];
  // Part B lies over part A: move it down onto A (overlapping by 1 cm) as the rest shape
  // would not overlap; no mesentery holds either part.
  const WorldModel m = worldFromPoints(q, r, 0.0, 0.5, Vec3::Zero());
  WorldState s = makeWorldState(m);
  FclContactQuery query(m);
  query.findSelfContacts(m, s);
  ASSERT_FALSE(s.self.empty());
  double min_gap0 = 1e9;
  for (const SelfContact& c : s.self) min_gap0 = std::min(min_gap0, -c.depth_m);
  HandleInput none;
  for (int k = 0; k < 3000; ++k) stepWorld(m, s, none, query, kDt);
  query.findSelfContacts(m, s);
  double max_depth = 0;
  for (const SelfContact& c : s.self) max_depth = std::max(max_depth, c.depth_m);
  EXPECT_LT(max_depth, 0.002);  // from 10 mm of overlap to under 2 mm
  EXPECT_LT(min_gap0, -0.008);
  EXPECT_TRUE(s.colon.q.allFinite());
}

// An L-shaped colon (straight, a 90-degree bend of radius 5 cm, straight), held firmly.
Points lShape() {
  std::vector<Vec3> pts;
  for (double x = 0; x < 0.30; x += 0.015) pts.emplace_back(x, 0, 0);
  for (int i = 0; i <= 6; ++i) {
    const double a = 0.5 * M_PI * i / 6;
    pts.emplace_back(0.30 + 0.05 * std::sin(a), 0.05 * (1 - std::cos(a)), 0);
  }
  for (double y = 0.065; y < 0.40; y += 0.015) pts.emplace_back(0.35, y, 0);
  Points q(3, static_cast<int>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) q.col(static_cast<int>(i)) = pts[i];
  return q;
}

TEST(ScopeInColon, PushedIntoABendStaysInsideTheWall) {
  const double r = 0.017;
  const WorldModel m = worldFromPoints(lShape(), r, 2000, 40, Vec3::Zero());
  WorldState s = makeWorldState(m);
  FclContactQuery q(m);
  HandleInput in;
  double max_depth = 0;
  for (int k = 0; k < 5500; ++k) {  // 10 cm/s for 0.55 m: through the bend
    in.insertion_m = 0.1 * k * kDt;
    stepWorld(m, s, in, q, kDt);
    for (const WallContact& c : s.wall) max_depth = std::max(max_depth, c.depth_m);
    for (int j = 0; j < s.scope.inside; ++j) ASSERT_TRUE(s.scope.p_W[j].allFinite());
    ASSERT_TRUE(s.colon.q.allFinite());
  }
  EXPECT_LT(max_depth, 0.006);  // stated tolerance: 6 mm beyond the wall at 10 cm/s
  // The tip went round the bend.
  EXPECT_GT(tipPosition(m.scope, s.scope).y(), 0.15);
}

TEST(ScopeInColon, PullingAlongAWallTakesMuTimesTheNormalLoad) {
  // A straight horizontal colon, held firmly; the scope lies on its floor under its own
  // weight N = rho_s L g and is withdrawn at 3 cm/s: the handle pulls with mu N.
  const double r = 0.017;
  Points q(3, 60);
  for (int i = 0; i < 60; ++i) q.col(i) = Vec3(0.015 * i, 0, 0);
  const Vec3 g(0, 0, -9.81);
  for (double mu : {0.1, 0.3}) {
    ColonModel colon = buildColonModelFromPoints(q, Eigen::VectorXd::Constant(60, r), 0.4, 1e5, 500, Vec3::Zero(),
                                                 std::make_shared<VoigtLaw>(28.9, 0.05));
    ScopeParams sp;
    sp.drag_Ns_per_m2 = 0;
    ContactParams cp;
    cp.friction_coefficient = mu;
    WorldModel m = makeWorldModel(std::move(colon), sp, cp);
    m.scope.gravity_m_per_s2 = g;
    WorldState s = makeWorldState(m);
    FclContactQuery query(m);
    HandleInput in;
    for (int k = 0; k < 3000; ++k) {  // insert 0.6 m and let it settle on the floor
      in.insertion_m = std::min(0.6, 0.3 * k * kDt);
      stepWorld(m, s, in, query, kDt);
    }
    // The normal load is what the contacts carry (near the anus part of the weight hangs
    // from the fixed entry point instead of resting on the floor).
    double pull_sum = 0, normal_sum = 0;
    int samples = 0;
    for (int k = 0; k < 3000; ++k) {  // withdraw at 3 cm/s
      in.insertion_m -= 0.03 * kDt;
      stepWorld(m, s, in, query, kDt);
      if (k > 500) {
        pull_sum += -s.scope.handle.force_N;
        for (const WallContact& c : s.wall) normal_sum += c.normal_force_N;
        ++samples;
      }
    }
    const double expected = mu * normal_sum / samples;
    EXPECT_GT(normal_sum / samples, 0.3 * 0.5 * 0.2 * 9.81);  // most of the weight rests on the floor
    EXPECT_NEAR(pull_sum / samples, expected, 0.05 * expected) << "mu = " << mu;
  }
}

TEST(World, SameInputsGiveBitIdenticalStates) {
  const WorldModel m = adultWorld();
  auto run = [&] {
    WorldState s = makeWorldState(m);
    FclContactQuery q(m);
    HandleInput in;
    for (int k = 0; k < 3000; ++k) {
      in.insertion_m = 0.1 * k * kDt;
      in.rotation_rad = 0.5 * std::sin(k * 2e-3);
      in.knob_updown_rad = 0.3;
      stepWorld(m, s, in, q, kDt);
    }
    return hashWorldState(s);
  };
  EXPECT_EQ(run(), run());
}

}  // namespace
}  // namespace colosim
