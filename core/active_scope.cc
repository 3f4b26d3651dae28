#include "core/active_scope.h"

#include <algorithm>
#include <cmath>

#include "core/rotation.h"

namespace colosim {

namespace {

// The bending stiffness K_b = EI/h of joint k [N m/rad].
double bendingStiffness(const ScopeModel& m, int k) { return m.joint_stiffness_Nm_per_rad[k].x(); }

Vec3 bendingOnly(Vec3 v) {
  v.z() = 0;
  return v;
}

}  // namespace

Vec3 actuatorLag(const Vec3& rest, const Vec3& target, double dt, double tau) {
  return rest + (1.0 - std::exp(-dt / tau)) * (target - rest);
}

Vec3 limitActuatorMoment(const Vec3& rest, const Vec3& omega, double kb, double limit) {
  Vec3 d = bendingOnly(rest - omega);
  const double moment = kb * d.norm();
  if (moment > limit) d *= limit / moment;
  Vec3 out = omega + d;
  out.z() = 0;
  return out;
}

Vec3 wireLimitedRest(const ScopeModel& m, const ScopeState& s, int k, const HandleInput& in) {
  const Vec3 knobs = restJointRotation(m, k, in);
  const double limit = m.params.knob_moment_limit_Nm;
  if (k >= m.bending_joints || !(limit > 0)) return knobs;
  const Vec3 omega = logSO3(s.R_WS[k + 1].transpose() * s.R_WS[k]);
  const double kb = bendingStiffness(m, k) * bendingStiffnessFactor(m, k, in);
  if (kb * bendingOnly(knobs - omega).norm() <= limit) return knobs;  // the knobs' own bits
  return limitActuatorMoment(knobs, omega, kb, limit);
}

double actuatorMoment(const ScopeModel& m, const ScopeState& s, int k) {
  const Vec3 omega = logSO3(s.R_WS[k + 1].transpose() * s.R_WS[k]);
  return bendingStiffness(m, k) * bendingOnly(s.joint_rest_rad[k] - omega).norm();
}

Vec3 leadBend(const ScopeState& s, double x) {
  x = std::clamp(x, 0.0, static_cast<double>(s.lead_count - 1));
  const int i = std::min(static_cast<int>(std::floor(x)), s.lead_count - 1);
  if (i + 1 >= s.lead_count) return s.lead_bend_rad[i];
  const double f = x - i;
  return (1 - f) * s.lead_bend_rad[i] + f * s.lead_bend_rad[i + 1];
}

Vec3 followTheLeaderTarget(const ScopeModel& m, const ScopeState& s, int k, double insertion_m) {
  // Joint k lies at depth L - (k+1) h from the anus; joint 0 was there when the insertion was L - k h.
  return bendingOnly(leadBend(s, insertion_m / m.h_m - k));
}

Vec3 contactMinimisingTarget(const ScopeModel& m, const ScopeState& s, int k, const Vec3& distal_moment_W) {
  const ActiveScopeParams& a = m.params.active;
  const Vec3 yield = bendingOnly(s.R_WS[k + 1].transpose() * distal_moment_W);
  const Vec3& rest = s.joint_rest_rad[k];
  return rest + (a.contact_gain / bendingStiffness(m, k)) * yield - (a.time_constant_s / a.contact_relax_s) * rest;
}

void recordLead(const ScopeModel& m, ScopeState& s, double previous_insertion_m) {
  const double h = m.h_m, L = s.input.insertion_m;
  const int last = std::min(static_cast<int>(s.lead_bend_rad.size()) - 1, static_cast<int>(std::floor(L / h + 1e-9)));
  const int first_new = std::max(1, static_cast<int>(std::floor(previous_insertion_m / h + 1e-9)) + 1);
  // Passed going in: the tip joint's bend now (the knobs').
  const Vec3 bend = restJointRotation(m, 0, s.input);
  for (int j = first_new; j <= last && j <= s.lead_count; ++j) {
    s.lead_bend_rad[j] = bend;
    s.lead_count = std::max(s.lead_count, j + 1);
  }
  // Missing below the insertion: the shaft's own bend where joint 0 was then (joint L/h - j).
  for (int j = s.lead_count; j <= last; ++j) {
    const int k = std::clamp(static_cast<int>(std::lround(L / h - j)), 0, m.segment_count - 2);
    s.lead_bend_rad[j] = bendingOnly(logSO3(s.R_WS[k + 1].transpose() * s.R_WS[k]));
    s.lead_count = j + 1;
  }
}

void updateActiveScope(const ScopeModel& m, ScopeState& s, double previous_insertion_m, double dt) {
  if (m.actuated_joints == 0 || s.joint_rest_rad.empty()) return;
  const ActiveScopeParams& a = m.params.active;
  recordLead(m, s, previous_insertion_m);
  // Contact-minimising: each agent hands the loads beyond it to its proximal neighbour, as
  // prefix sums from the tip: the total force F and moment about the origin M0 of the loads
  // on segments 0..k give their moment about joint k, M0 - x_k x F.
  const bool minimising = a.strategy == ActiveStrategy::kContactMinimising;
  if (minimising) {
    std::fill(s.segment_load_force_N.begin(), s.segment_load_force_N.end(), Vec3::Zero());
    std::fill(s.segment_load_moment_Nm.begin(), s.segment_load_moment_Nm.end(), Vec3::Zero());
    for (const ScopeLoad& load : s.loads) {
      if (load.segment < 0 || load.segment >= static_cast<int>(s.segment_load_force_N.size())) continue;
      s.segment_load_force_N[load.segment] += load.force_N;
      s.segment_load_moment_Nm[load.segment] += (s.p_W[load.segment] + load.r_W).cross(load.force_N);
    }
  }
  Vec3 distal_force_N = Vec3::Zero(), distal_moment0_Nm = Vec3::Zero();
  for (int k = 0; k < m.first_actuated_joint && minimising; ++k) {
    distal_force_N += s.segment_load_force_N[k];
    distal_moment0_Nm += s.segment_load_moment_Nm[k];
  }
  for (int k = m.first_actuated_joint; k < m.actuated_joints; ++k) {
    if (k >= s.inside) {  // outside: straight along the entry
      s.joint_rest_rad[k].setZero();
      continue;
    }
    Vec3 target;
    if (minimising) {
      distal_force_N += s.segment_load_force_N[k];
      distal_moment0_Nm += s.segment_load_moment_Nm[k];
      const Vec3 joint_W = s.p_W[k] - 0.5 * m.h_m * s.R_WS[k].col(2);  // segment k's proximal end
      target = contactMinimisingTarget(m, s, k, distal_moment0_Nm - joint_W.cross(distal_force_N));
    } else {
      target = followTheLeaderTarget(m, s, k, s.input.insertion_m);
    }
    const Vec3 omega = logSO3(s.R_WS[k + 1].transpose() * s.R_WS[k]);
    s.joint_rest_rad[k] = limitActuatorMoment(actuatorLag(s.joint_rest_rad[k], target, dt, a.time_constant_s), omega,
                                              bendingStiffness(m, k), a.joint_torque_limit_Nm);
  }
}

}  // namespace colosim
