// The active scope (core/active_scope.h): actuator lag and torque limit, follow-the-leader
// in free space, contact-minimising against a wall, determinism.
#include "core/active_scope.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "core/rotation.h"
#include "core/scope_step.h"
#include "step.h"

namespace colosim {
namespace {

ActiveScopeParams active(ActiveStrategy strategy, double tau_s = 0.02, double limit_Nm = 0.5) {
  ActiveScopeParams a;
  a.enabled = true;
  a.strategy = strategy;
  a.time_constant_s = tau_s;
  a.joint_torque_limit_Nm = limit_Nm;
  a.actuated_length_m = 0.6;
  return a;
}

// A scope entering at the origin along +x, d2 (up) along +z, in free space without gravity.
ScopeModel scope(const ActiveScopeParams& a, const Vec3& gravity = Vec3::Zero(), double bending_section_m = 0.09) {
  ScopeParams p;
  p.active = a;
  p.bending_section_length_m = bending_section_m;
  return buildScopeModel(p, Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 0, 1), gravity);
}

double distanceToPolyline(const Vec3& x, const std::vector<Vec3>& path) {
  double best = 1e300;
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const Vec3 d = path[i + 1] - path[i];
    const double t = d.squaredNorm() > 0 ? std::clamp((x - path[i]).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (path[i] + t * d - x).norm());
  }
  return best;
}

// The steered insertion: straight to 0.12 m, the knob up to 40 deg by 0.27 m, back to 0
// by 0.42 m, straight on to 0.5 m, at 5 cm/s (a path the shaft can take: the knobs turn
// slowly against the advance, so the tip's sideways swing does not kink its path). Returns the tip's path (every step) and
// calls `each` after every step.
std::vector<Vec3> steeredInsertion(const ScopeModel& m, ScopeState& s,
                                   const std::function<void(const ScopeState&)>& each = {}) {
  std::vector<Vec3> path{tipPosition(m, s)};
  const double speed = 0.05, up = 40 * M_PI / 180;
  HandleInput in;
  for (int n = 1; n <= 10000; ++n) {
    const double L = speed * n * kDt;
    in.insertion_m = L;
    in.knob_updown_rad = L < 0.12 ? 0.0 : L < 0.27 ? up * (L - 0.12) / 0.15 : L < 0.42 ? up * (0.42 - L) / 0.15 : 0.0;
    stepScope(m, s, in, kDt);
    path.push_back(tipPosition(m, s));
    if (each) each(s);
  }
  return path;
}

// Largest distance of the shaft's segment centres (proximal of the steerable tip) from the tip's path [m].
double shaftDeviation(const ScopeModel& m, const ScopeState& s, const std::vector<Vec3>& path) {
  double worst = 0;
  for (int k = m.bending_joints; k < s.inside; ++k) worst = std::max(worst, distanceToPolyline(s.p_W[k], path));
  return worst;
}

TEST(ActiveScope, LagReaches63PercentAtTheTimeConstant) {
  // The free function: n = tau/dt steps of a unit step.
  const double tau = 0.05;
  Vec3 rest = Vec3::Zero();
  for (int n = 0; n < 50; ++n) rest = actuatorLag(rest, Vec3(1, 0, 0), kDt, tau);
  EXPECT_NEAR(rest.x(), 1 - std::exp(-1.0), 1e-12);

  // In the scope: a straight scope given a bent lead (0.1 rad about d1 from sample 10 on)
  // follows it with the actuators' lag.
  const ScopeModel m = scope(active(ActiveStrategy::kFollowTheLeader, tau, 10.0));
  ScopeState s = makeScopeState(m);
  HandleInput in;
  for (int n = 1; n <= 600; ++n) {
    in.insertion_m = 0.3 * n / 600.0;
    stepScope(m, s, in, kDt);
  }
  ASSERT_EQ(s.lead_count, 21);
  for (int j = 10; j < s.lead_count; ++j) s.lead_bend_rad[j] = Vec3(0.1, 0, 0);
  const int k = 8;  // sample 20 - 8 = 12: 0.1 rad
  for (int n = 0; n < 50; ++n) stepScope(m, s, in, kDt);
  const double target = followTheLeaderTarget(m, s, k, s.input.insertion_m).norm();
  EXPECT_NEAR(target, 0.1, 1e-9);
  EXPECT_NEAR(s.joint_rest_rad[k].norm() / target, 1 - std::exp(-1.0), 0.01);
  for (int n = 0; n < 250; ++n) stepScope(m, s, in, kDt);
  EXPECT_NEAR(s.joint_rest_rad[k].norm() / target, 1.0, 0.01);  // 6 tau: 99.75 %
}

TEST(ActiveScope, ActuatorMomentNeverExceedsTheTorqueLimit) {
  // A weak actuator (0.02 N m) asked for a sharp path, under gravity: it saturates.
  const double limit = 0.02;
  const ScopeModel m = scope(active(ActiveStrategy::kFollowTheLeader, 0.02, limit), Vec3(0, 0, -9.81));
  ScopeState s = makeScopeState(m);
  double worst = 0;
  int at_limit = 0;
  steeredInsertion(m, s, [&](const ScopeState& st) {
    for (int k = m.first_actuated_joint; k < std::min(m.actuated_joints, st.inside); ++k) {
      const double moment = actuatorMoment(m, st, k);
      worst = std::max(worst, moment);
      if (moment > 0.999 * limit) ++at_limit;
    }
  });
  EXPECT_LE(worst, limit * (1 + 1e-9));
  EXPECT_GT(at_limit, 100);  // the limit was reached: the assertion above is not idle
}

TEST(ActiveScope, FollowTheLeaderShaftFollowsTheTipsPathInFreeSpace) {
  const ScopeModel ftl = scope(active(ActiveStrategy::kFollowTheLeader));
  ScopeState s = makeScopeState(ftl);
  const std::vector<Vec3> path = steeredInsertion(ftl, s);
  const double worst_active = shaftDeviation(ftl, s, path);
  // The passive scope on the same inputs: its shaft stays on the entry line.
  const ScopeModel passive = scope(ActiveScopeParams());
  ScopeState p = makeScopeState(passive);
  const std::vector<Vec3> passive_path = steeredInsertion(passive, p);
  const double worst_passive = shaftDeviation(passive, p, passive_path);
  // The path turned: the tip ends well off the entry line.
  EXPECT_GT(std::hypot(path.back().y(), path.back().z()), 0.05);
  EXPECT_LT(worst_active, 0.003) << "passive " << worst_passive;
  EXPECT_GT(worst_passive, 0.01) << "active " << worst_active;
  RecordProperty("shaft_deviation_active_m", std::to_string(worst_active));
  RecordProperty("shaft_deviation_passive_m", std::to_string(worst_passive));
  std::printf("shaft deviation from the tip's path: active %.2f mm, passive %.2f mm\n", 1e3 * worst_active,
              1e3 * worst_passive);

  // Withdrawing 10 cm at 5 cm/s keeps the record and the joints keep following it (the
  // shape flows back along the path; 3.6 mm measured).
  const int count = s.lead_count;
  HandleInput in = s.input;
  for (int n = 0; n < 2000; ++n) {
    in.insertion_m -= 0.05 * kDt;
    stepScope(ftl, s, in, kDt);
  }
  EXPECT_EQ(s.lead_count, count);
  EXPECT_LT(shaftDeviation(ftl, s, path), 0.005);
}

// A scope pushed along an inclined wall: the wall y < 0.3 (x - 0.15) (outside the lumen
// beyond the plane), penalty 1000 N/m and 1 N s/m per interaction point, no friction;
// pushed in to 0.35 m over 1.4 s, then held for 0.6 s. Returns the total wall force
// averaged over the last 0.5 s [N] (one step's force is no measure: an eager agent makes
// the scope flail on and off the wall).
double pressedOnAWall(const ScopeModel& m, ScopeState& s, const std::function<void(const ScopeState&)>& each = {}) {
  const Vec3 n = Vec3(-0.3, 1, 0).normalized();  // into the free side
  HandleInput in;
  double sum = 0;
  int summed = 0;
  for (int step = 1; step <= 2000; ++step) {
    in.insertion_m = 0.35 * std::min(1.0, step / 1400.0);
    s.loads.clear();
    double total = 0;
    for (int k = 0; k < s.inside; ++k)
      for (const Vec3& q : m.interaction_points_S) {
        const Vec3 r = s.R_WS[k] * q, x = s.p_W[k] + r;
        const double depth = -(x - Vec3(0.15, 0, 0)).dot(n);
        if (depth <= 0) continue;
        const Vec3 v = s.v_W[k] + s.w_W[k].cross(r);
        ScopeLoad load;
        load.segment = k;
        load.r_W = r;
        const double f = std::max(0.0, 1000 * depth - 1.0 * v.dot(n));
        load.force_N = f * n;
        load.stiffness_N_per_m = 1000 * n * n.transpose();
        load.damping_Ns_per_m = 1.0 * n * n.transpose();
        s.loads.push_back(load);
        total += f;
      }
    if (step > 1500) sum += total, ++summed;
    stepScope(m, s, in, kDt);
    if (each) each(s);
  }
  return sum / summed;
}

// The contact-minimising agents against a wall the scope is pushed along (issue 20): each
// joint yields to the moment of the loads distal of it, so the scope bends away from the
// wall ahead of the contact instead of being bent by it. Over every agent setting tried
// in session 19 (time constant 0.02 / 0.05 / 0.2 s x gain 0.5 / 1 / 2 / 5), the wall force
// averaged over the hold falls below half the passive scope's (measured 0.000-0.056 N
// against 0.130 N). The agents relax towards straight without contact (1 s), so the scope
// taps the wall now and then: its largest force over the hold reaches 0.37 N at 0.02 s
// and gain 1 (passive 0.148 N); bounded here by 3x the passive's, where the rule session 19
// had flailed to 1.9 N. That rule (each joint's own neighbourhood, distal minus proximal
// moments) never lowered the average (0.134-0.433 N).
TEST(ActiveScope, ContactMinimisingLowersTheWallForce) {
  // A scope whose steerable tip is one joint: the wall meets the actuated part.
  // The largest total wall force over the hold (after the first 1500 steps).
  auto largestOverTheHold = [](int& step, double& largest_N) {
    return [&step, &largest_N](const ScopeState& st) {
      if (++step <= 1500) return;
      double total = 0;
      for (const ScopeLoad& l : st.loads) total += l.force_N.norm();
      largest_N = std::max(largest_N, total);
    };
  };
  const ScopeModel passive = scope(ActiveScopeParams(), Vec3::Zero(), 0.015);
  ScopeState p = makeScopeState(passive);
  int passive_step = 0;
  double passive_largest_N = 0;
  const double f_passive = pressedOnAWall(passive, p, largestOverTheHold(passive_step, passive_largest_N));
  EXPECT_GT(f_passive, 0.1);  // the scope is pressed on the wall
  const double limit = 0.5;
  for (double tau : {0.02, 0.05, 0.2})
    for (double gain : {0.5, 1.0, 2.0, 5.0}) {
      ActiveScopeParams agents = active(ActiveStrategy::kContactMinimising, tau, limit);
      agents.contact_gain = gain;
      const ScopeModel cm = scope(agents, Vec3::Zero(), 0.015);
      ScopeState a = makeScopeState(cm);
      double worst_moment = 0, largest_N = 0;
      int step = 0;
      const auto largest = largestOverTheHold(step, largest_N);
      const double f_active = pressedOnAWall(cm, a, [&](const ScopeState& st) {
        for (int k = cm.first_actuated_joint; k < std::min(cm.actuated_joints, st.inside); ++k)
          worst_moment = std::max(worst_moment, actuatorMoment(cm, st, k));
        largest(st);
      });
      std::printf("tau %.2f s, gain %.1f: wall force over the hold %.4f N (largest %.4f N); passive %.4f N (%.4f N)\n",
                  tau, gain, f_active, largest_N, f_passive, passive_largest_N);
      EXPECT_LT(f_active, 0.5 * f_passive) << "tau " << tau << " gain " << gain;
      EXPECT_LT(largest_N, 3 * passive_largest_N) << "tau " << tau << " gain " << gain;
      EXPECT_LE(worst_moment, limit * (1 + 1e-9));
    }
}

TEST(ActiveScope, TwoRunsAreBitIdentical) {
  for (ActiveStrategy strategy : {ActiveStrategy::kFollowTheLeader, ActiveStrategy::kContactMinimising}) {
    const ScopeModel m = scope(active(strategy), Vec3(0, 0, -9.81));
    ScopeState a = makeScopeState(m), b = makeScopeState(m);
    if (strategy == ActiveStrategy::kFollowTheLeader) {
      steeredInsertion(m, a);
      steeredInsertion(m, b);
    } else {
      pressedOnAWall(m, a);
      pressedOnAWall(m, b);
    }
    const std::vector<double> sa = getScopeState(a), sb = getScopeState(b);
    ASSERT_EQ(sa.size(), sb.size());
    EXPECT_EQ(std::memcmp(sa.data(), sb.data(), sa.size() * sizeof(double)), 0);
    // The snapshot carries the actuators' state: restoring it gives the same next step.
    ScopeState c = makeScopeState(m);
    setScopeState(sa, c);
    EXPECT_EQ(getScopeState(c), sa);
  }
}

TEST(ActiveScope, PassiveScopeSnapshotHasNoActiveState) {
  const ScopeModel m = scope(ActiveScopeParams());
  EXPECT_EQ(m.actuated_joints, 0);
  const ScopeState s = makeScopeState(m);
  EXPECT_TRUE(s.joint_rest_rad.empty());
  EXPECT_EQ(getScopeState(s).size(), 16u + 18u * m.segment_count);
}

}  // namespace
}  // namespace colosim
