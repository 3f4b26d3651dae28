#include "core/scope_step.h"

#include <algorithm>
#include <cmath>

#include "core/active_scope.h"
#include "core/rotation.h"
#include "core/scope_grip.h"
#include "core/step_lanes.h"

namespace colosim {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

namespace {

inline Vec6 stacked(const Vec3& a, const Vec3& b) {
  Vec6 x;
  x << a, b;
  return x;
}

// The terms of joint k (between segment k, distal, and k+1, proximal) at the current
// state: generalised forces on both, and their 6x6 stiffness and damping blocks.
struct JointTerms {
  Vec6 f_distal, f_proximal;  // generalised forces (force; torque)
  Mat6 K_dd, K_pp, K_dp;      // stiffness blocks: (k,k), (k+1,k+1), (k,k+1)
};

JointTerms jointTerms(const ScopeModel& m, const ScopeState& s, int k, const HandleInput& in) {
  const double hh = 0.5 * m.h_m;
  const Vec3 d3k = s.R_WS[k].col(2), d3p = s.R_WS[k + 1].col(2);
  // Position: the distal segment's proximal end meets the proximal segment's distal end.
  // gap rate = Jd u_k + Jp u_{k+1} with Jd = [I, Sd], Jp = [-I, Sp], S = (h/2)[d3]x, so
  // S w = (h/2) d3 x w, and the products of two such matrices are outer products:
  // [a]x [b]x = b a^T - (a . b) I.
  const Vec3 gap = (s.p_W[k] - hh * d3k) - (s.p_W[k + 1] + hh * d3p);
  const double kj = m.params.joint_stiffness_N_per_m;
  const Vec3 gap_rate = s.v_W[k] + hh * d3k.cross(s.w_W[k]) - s.v_W[k + 1] + hh * d3p.cross(s.w_W[k + 1]);
  const Vec3 fg = kj * (gap + m.params.joint_damping_s * gap_rate);

  // Rotation: bending and torsion against the rest rotation.
  const Mat3 R_rel = s.R_WS[k + 1].transpose() * s.R_WS[k];
  Mat3 jr_inverse;
  const Vec3 omega = logSO3WithJacobian(R_rel, &jr_inverse);
  const Vec3 err = omega - jointRestRotation(m, s, k, in);
  const Mat3 A = jr_inverse * s.R_WS[k].transpose();
  const Vec3 rel_rate = A * (s.w_W[k] - s.w_W[k + 1]);
  Vec3 kd = m.joint_stiffness_Nm_per_rad[k];
  const double ei_factor = bendingStiffnessFactor(m, k, in);  // the variable-stiffness level (1 elsewhere)
  kd.x() *= ei_factor;
  kd.y() *= ei_factor;
  const Vec3 moment = kd.cwiseProduct(err + m.params.joint_damping_s * rel_rate);  // joint frame
  const Vec3 tau = A.transpose() * moment;  // world torque on the distal segment is -tau

  JointTerms t;
  // Generalised forces -J^T fg (J^T = [I; S^T] with S^T = -S), plus the rotational moment.
  t.f_distal << -fg, hh * d3k.cross(fg) - tau;
  t.f_proximal << fg, hh * d3p.cross(fg) + tau;
  // Gauss-Newton stiffness kj J^T J from 3x3 pieces, plus A^T K A on the rotations.
  const Mat3 KA = kd.asDiagonal() * A;
  const Mat3 AKA = A.transpose() * KA;
  const Mat3 I3 = Mat3::Identity();
  const double c2 = kj * hh * hh;
  const Mat3 kSd = (kj * hh) * skew(d3k), kSp = (kj * hh) * skew(d3p);
  t.K_dd.topLeftCorner<3, 3>() = kj * I3;
  t.K_dd.topRightCorner<3, 3>() = kSd;
  t.K_dd.bottomLeftCorner<3, 3>() = -kSd;
  t.K_dd.bottomRightCorner<3, 3>() = c2 * (I3 - d3k * d3k.transpose()) + AKA;
  t.K_pp.topLeftCorner<3, 3>() = kj * I3;
  t.K_pp.topRightCorner<3, 3>() = -kSp;
  t.K_pp.bottomLeftCorner<3, 3>() = kSp;
  t.K_pp.bottomRightCorner<3, 3>() = c2 * (I3 - d3p * d3p.transpose()) + AKA;
  t.K_dp.topLeftCorner<3, 3>() = -kj * I3;
  t.K_dp.topRightCorner<3, 3>() = kSp;
  t.K_dp.bottomLeftCorner<3, 3>() = kSd;
  t.K_dp.bottomRightCorner<3, 3>() = c2 * (d3k.dot(d3p) * I3 - d3p * d3k.transpose()) - AKA;
  return t;
}

// ---------------------------------------------------------------------------------------
// The stages of advanceScope(), in order.

// Inputs: the segments wholly inside after the step (those that crossed the anus by the
// insertion) and the simulated ones: those and the one straddling the anus, while there is
// a kinematic segment behind it for its proximal joint.
int insideAfter(const ScopeModel& m, const HandleInput& in, int inside_set) {
  const int K = m.segment_count;
  return inside_set >= 0 ? inside_set : std::min(K - 1, static_cast<int>(std::floor(in.insertion_m / m.h_m + 1e-9)));
}

int simulatedAfter(const ScopeModel& m, const HandleInput& in, int inside) {
  return inside + 1 < m.segment_count && in.insertion_m > 0 ? inside + 1 : inside;
}

// The leaving segment: a segment withdrawn out of the simulated chain (its distal end has
// just come out through the sphincter) becomes kinematic where the chain left it, and
// straightens over the next segment length of withdrawal (exitPose): the sphincter held
// it only as firmly as its stiffness, so it may be off its straight pose by a fraction of
// a millimetre, which put straight at once would open the joint to the chain against the
// 2e6 N/m joint penalty.
// (Invariant: tilted_segment is -1 or the first kinematic segment, s.simulated.)
// Returns the tilted segment when it is pushed back in before it came out (it rejoins as
// it is), else -1.
int trackTiltedSegment(const ScopeModel& m, ScopeState& s, int simulated) {
  int rejoined = -1;
  if (simulated < s.simulated) {
    // Its offset from the straight pose of the inputs its pose is at: the last step's.
    Vec3 p;
    Mat3 R_straight;
    kinematicPose(m, simulated, s.input.insertion_m, s.input.rotation_rad, &p, &R_straight);
    s.tilted_segment = simulated;
    s.tilt_rad = logSO3(s.R_WS[simulated] * R_straight.transpose());
    s.tilt_offset_m = s.p_W[simulated] - p;
  } else if (simulated > s.simulated) {
    rejoined = s.tilted_segment;
    s.tilted_segment = -1;
  }
  return rejoined;
}

// The outside part moves with the handle. A segment that starts to be simulated this step
// (it has reached the anus) joins from where it was at the start of the step (its
// kinematic pose of the last inputs) with the handle's velocity, like the simulated
// segments: the integration carries it on. It joins straight and on the entry axis, as the
// sphincter and the outside part hold it, so nothing is posed at the join.
// (Placed at the new inputs' pose and then integrated, it ran dt * speed ahead of its
// base: 0.7 mm at 1 m/s, which the 2e6 N/m joint read as a pull of up to 495 N on the
// handle in extreme_all.)
void moveOutsidePart(const ScopeModel& m, ScopeState& s, const HandleInput& in, int simulated, int rejoined,
                     double dt) {
  const int K = m.segment_count;
  const Vec3 e = m.R_W_entry.col(2);
  const double insertion_rate = (in.insertion_m - s.input.insertion_m) / dt;
  const double rotation_rate = (in.rotation_rad - s.input.rotation_rad) / dt;
  for (int k = std::min(simulated, s.simulated); k < K; ++k) {
    if (k < simulated && k < s.simulated) continue;
    if (k == rejoined) continue;  // keeps its pose and the velocity it came out with
    if (k == s.tilted_segment) {
      // The velocity of its move this step, for the joint's damping.
      const Vec3 p0 = s.p_W[k];
      const Mat3 R0 = s.R_WS[k];
      exitPose(m, k, in.insertion_m, in.rotation_rad, s.tilt_rad, s.tilt_offset_m, &s.p_W[k], &s.R_WS[k]);
      s.v_W[k] = (s.p_W[k] - p0) / dt;
      s.w_W[k] = logSO3(s.R_WS[k] * R0.transpose()) / dt;
      continue;
    }
    if (k >= simulated) kinematicPose(m, k, in.insertion_m, in.rotation_rad, &s.p_W[k], &s.R_WS[k]);
    s.v_W[k] = insertion_rate * e;
    s.w_W[k] = rotation_rate * e;
  }
}

// Segment terms: the system and forces cleared, then per segment its mass (and the drag's
// implicit part) and inertia, gravity and drag.
void addSegmentTerms(const ScopeModel& m, ScopeState& s, int simulated, double dt) {
  const int n = 6 * simulated;
  double* f = s.force.data();
  double* rhs = s.rhs.data();
  std::fill(f, f + n, 0.0);
  std::fill(rhs, rhs + n, 0.0);
  s.system.setZero(simulated);
  const double drag = m.params.drag_Ns_per_m2 * m.h_m;
  for (int k = 0; k < simulated; ++k) {
    Mat6 Mk = Mat6::Zero();
    Mk.topLeftCorner<3, 3>() = (m.segment_mass_kg + dt * drag) * Mat3::Identity();
    Mk.bottomRightCorner<3, 3>() =
        s.R_WS[k] * m.segment_inertia_kgm2.asDiagonal() * s.R_WS[k].transpose();
    s.system.diag(k) += Mk;
    const Vec3 fk = m.segment_mass_kg * m.gravity_m_per_s2 - drag * s.v_W[k];
    for (int c = 0; c < 3; ++c) f[6 * k + c] += fk(c);
  }
}

// The last joint (between the last simulated segment and the outside part, the base) at
// the start of the step, for the handle reaction.
struct BaseJoint {
  Vec6 f0 = Vec6::Zero();  // its generalised force on the base
  Vec6 u0 = Vec6::Zero();  // the distal segment's velocity
  Mat6 K = Mat6::Zero();   // its stiffness block (base row, distal segment column)
};

// Joint terms: joint k joins segment k and k+1 (k+1 == simulated: the base); its forces,
// and dt C + dt^2 K with C = beta K in the system and -dt^2 K u in the rhs.
BaseJoint addJointTerms(const ScopeModel& m, ScopeState& s, const HandleInput& in, int simulated, double dt) {
  double* f = s.force.data();
  double* rhs = s.rhs.data();
  const double beta = m.params.joint_damping_s;
  BaseJoint base;
  const double sys_k = dt * beta + dt * dt;  // dt C + dt^2 K with C = beta K
  for (int k = 0; k < simulated; ++k) {
    const JointTerms t = jointTerms(m, s, k, in);
    const bool proximal_simulated = (k + 1 < simulated);
    const Vec6 uk = stacked(s.v_W[k], s.w_W[k]);
    if (!proximal_simulated) base.f0 = t.f_proximal, base.K = t.K_dp.transpose(), base.u0 = uk;
    for (int c = 0; c < 6; ++c) f[6 * k + c] += t.f_distal(c);
    s.system.diag(k) += sys_k * t.K_dd;
    Vec6 Ku_k = t.K_dd * uk;
    if (proximal_simulated) {
      const Vec6 up = stacked(s.v_W[k + 1], s.w_W[k + 1]);
      Ku_k += t.K_dp * up;
      const Vec6 Ku_p = t.K_pp * up + t.K_dp.transpose() * uk;
      for (int c = 0; c < 6; ++c) {
        f[6 * (k + 1) + c] += t.f_proximal(c);
        rhs[6 * (k + 1) + c] -= dt * dt * Ku_p(c);
      }
      s.system.diag(k + 1) += sys_k * t.K_pp;
      s.system.below(k) += sys_k * t.K_dp.transpose();  // block (k+1, k)
    }
    for (int c = 0; c < 6; ++c) rhs[6 * k + c] -= dt * dt * Ku_k(c);
  }
  return base;
}

// The velocity of segment k's point at lever r_W from its centre: v + w x r [m/s].
inline Vec3 pointVelocity(const ScopeState& s, int k, const Vec3& r_W) { return s.v_W[k] + s.w_W[k].cross(r_W); }

// One load at a point of simulated segment k: its force and moment, and its stiffness and
// damping (point velocity v + w x r = J u with J = [I, -[r]x]; J^T = [I; [r]x]).
void addLoad(ScopeState& s, const ScopeLoad& load, double dt) {
  double* f = s.force.data();
  double* rhs = s.rhs.data();
  const int k = load.segment;
  const Mat3 Rx = skew(load.r_W);
  const Vec3 v_point = pointVelocity(s, k, load.r_W);
  const Vec3 Kv = load.stiffness_N_per_m * v_point;
  const Vec3 torque = load.r_W.cross(load.force_N), Ktorque = load.r_W.cross(Kv);
  for (int c = 0; c < 3; ++c) {
    f[6 * k + c] += load.force_N(c);
    f[6 * k + 3 + c] += torque(c);
    rhs[6 * k + c] -= dt * dt * Kv(c);
    rhs[6 * k + 3 + c] -= dt * dt * Ktorque(c);
  }
  const Mat3 H = dt * load.damping_Ns_per_m + dt * dt * load.stiffness_N_per_m;
  const Mat3 HR = H * Rx;
  Mat6 B;
  B << H, -HR, Rx * H, -Rx * HR;
  s.system.diag(k) += B;
}

// Loads (contacts) at points of the simulated segments, with their stiffness and damping.
void addLoadTerms(ScopeState& s, int simulated, double dt) {
  for (const ScopeLoad& load : s.loads)
    if (load.segment >= 0 && load.segment < simulated) addLoad(s, load, dt);
}

// The sphincter: a ring at the anus holding the straddling segment (the last simulated one,
// when it is not wholly inside) at the scope's point that crosses the anus, arclength L
// from the tip, laterally only (the insertion slides it through): a spring-damper towards
// the entry axis, k P (x - p_anus) with P = I - e e^T.
// On a chain of rigid segments the ring must hand the bend at the anus from the
// straddling segment's distal joint to its proximal one as the segment goes in (a
// continuous tube bends where it crosses the ring). The segment turns about its proximal
// joint against that joint's bending stiffness kb and the ring's lever: k c^2, with c the
// ring's distance from the proximal joint. A ring of constant k does it within the last
// sqrt(kb / k) of the segment (0.1 mm at 1e6 N/m), a swing of the chain and a couple of
// ring and joint of ~M sqrt(k / kb) / 2 (50 N for a 0.18 N m bend); a soft one leaves the
// segment free to swing when it joins. So the ring holds with k = kb / d^2, d = L - k h
// the depth of the segment's distal end, up to the sphincter's stiffness: the segment
// joins straight (d = 0: the sphincter's stiffness) and turns by 1 / (2 + ((h - d) / d)^2)
// of the bend as it goes in: a third at d = h / 2 (k c^2 = kb), half when it is in.
// The ring's load on segment k, with the point's velocity at the start of the step.
struct SphincterLoad {
  ScopeLoad load;                    // segment -1: no straddling segment
  Vec3 v0_m_per_s = Vec3::Zero();
};

SphincterLoad sphincterLoad(const ScopeModel& m, const ScopeState& s, const HandleInput& in, int k) {
  const Vec3 e = m.R_W_entry.col(2);
  const Mat3 P = Mat3::Identity() - e * e.transpose();
  const Vec3 kb = m.joint_stiffness_Nm_per_rad[k];  // of its proximal joint [N m/rad]
  const double bending = 0.5 * (kb.x() + kb.y()) * bendingStiffnessFactor(m, k, in);
  const double depth = std::max(in.insertion_m - k * m.h_m, 0.0);  // of its distal end [m]
  const double cap = m.params.sphincter_stiffness_N_per_m;
  const double stiffness = depth * depth * cap > bending ? bending / (depth * depth) : cap;
  SphincterLoad ring;
  ScopeLoad& l = ring.load;
  l.segment = k;
  l.r_W = ((k + 0.5) * m.h_m - in.insertion_m) * s.R_WS[k].col(2);
  const Vec3 x = s.p_W[k] + l.r_W;
  ring.v0_m_per_s = pointVelocity(s, k, l.r_W);
  l.stiffness_N_per_m = stiffness * P;
  l.damping_Ns_per_m = m.params.joint_damping_s * stiffness * P;
  l.force_N = -(l.stiffness_N_per_m * (x - m.p_W_anus) + l.damping_Ns_per_m * ring.v0_m_per_s);
  return ring;
}

// Returns the ring's load at the start of the step (segment -1: no straddling segment).
SphincterLoad addSphincterTerms(const ScopeModel& m, ScopeState& s, const HandleInput& in, int inside, int simulated,
                                double dt) {
  SphincterLoad ring;
  ring.load.segment = -1;
  if (simulated <= inside) return ring;
  ring = sphincterLoad(m, s, in, simulated - 1);
  addLoad(s, ring.load, dt);
  return ring;
}

// The ring's force over the step, as the solve took it (backward Euler, like the handle's):
// f0 - K dt v - C (v - v0) with v the point's velocity after the step, v0 before.
Vec3 sphincterForceOverStep(const ScopeState& s, const SphincterLoad& ring, double dt) {
  const ScopeLoad& l = ring.load;
  if (l.segment < 0) return Vec3::Zero();
  const Vec3 v = pointVelocity(s, l.segment, l.r_W);
  return l.force_N - dt * (l.stiffness_N_per_m * v) - l.damping_Ns_per_m * (v - ring.v0_m_per_s);
}

// Solve (M + dt C + dt^2 K) du = dt f - dt^2 K u on the simulated segments: a block
// tridiagonal system (6 x 6 blocks), by block Cholesky. Limit: a failed or non-finite
// solve gives du = 0 and s.solver_ok = false (integrateSegments() then stops the segments
// rather than carry NaN on).
void solveVelocityChange(ScopeState& s, int simulated, double dt) {
  const int n = 6 * simulated;
  const double* f = s.force.data();
  double* rhs = s.rhs.data();
  for (int i = 0; i < n; ++i) rhs[i] += dt * f[i];
  s.limited_segments = 0;
  s.asked_speed_m_per_s = s.asked_spin_rad_per_s = 0;
  s.solver_ok = s.system.factorize(simulated);
  if (s.solver_ok) {
    s.system.solveInPlace(simulated, rhs);
    for (int i = 0; i < n; ++i) s.solver_ok = s.solver_ok && std::isfinite(rhs[i]);
  }
  if (!s.solver_ok) std::fill(rhs, rhs + n, 0.0);
}

// The lens guard: the lens (the tip face's centre, on the scope's axis) must not pass the
// wall it faces. A penalty wall lets any frontal load indent it; this unilateral
// constraint at the velocity level stops the lens where the step would take it beyond
// s.lens_wall.gap_m: with a = (v + w x r) . n - v_wall the lens's speed into the wall after
// the solve (r: lens minus tip centre), if a dt > gap the impulse P (along -n) that brings
// a to gap / dt is applied to the whole chain: du -= P A^-1 J^T, with J = [n^T, (r x n)^T]
// on the tip segment and A the step's matrix (one more solve with its factors). The
// chain, its joints and the handle feel it; the caller passes -P to the wall.
void guardLens(const ScopeModel& m, ScopeState& s, int simulated, double dt,
               const std::atomic<bool>* wall_speed_ready) {
  s.lens_impulse_Ns = 0;
  const ScopeState::LensWall& wall = s.lens_wall;
  if (!wall.active || !s.solver_ok || simulated == 0) return;
  if (wall_speed_ready) waitUntilSet(*wall_speed_ready);
  double* du = s.rhs.data();
  const Vec3& n = wall.n_W;
  const Vec3 r = s.R_WS[0] * m.tip_face_points_S[0];
  const Vec3 rn = r.cross(n);
  const Vec3 v = s.v_W[0] + Vec3(du[0], du[1], du[2]);
  const Vec3 w = s.w_W[0] + Vec3(du[3], du[4], du[5]);
  const double a = (v + w.cross(r)).dot(n) - wall.wall_speed_m_per_s;
  const double a_max = wall.gap_m / dt;
  if (!(a > a_max)) return;
  double* x = s.guard_response.data();
  std::fill(x, x + 6 * simulated, 0.0);
  for (int c = 0; c < 3; ++c) x[c] = n(c), x[3 + c] = rn(c);
  s.system.solveInPlace(simulated, x);
  const double response = n.dot(Vec3(x[0], x[1], x[2])) + rn.dot(Vec3(x[3], x[4], x[5]));
  if (!(response > 0) || !std::isfinite(response)) return;
  const double impulse = (a - a_max) / response;
  for (int i = 0; i < 6 * simulated; ++i) du[i] -= impulse * x[i];
  s.lens_impulse_Ns = impulse;
}

// Integrate the simulated segments: u += du, x += dt u. Limit: a segment faster than the
// solve is trusted with is slowed to that speed or spin.
void integrateSegments(const ScopeModel& m, ScopeState& s, int simulated, double dt) {
  const double* rhs = s.rhs.data();
  const double v_max = m.params.max_speed_m_per_s, w_max = m.params.max_spin_rad_per_s;
  for (int k = 0; k < simulated; ++k) {
    if (!s.solver_ok) {
      s.v_W[k].setZero();
      s.w_W[k].setZero();
    }
    s.v_W[k] += Vec3(rhs[6 * k], rhs[6 * k + 1], rhs[6 * k + 2]);
    s.w_W[k] += Vec3(rhs[6 * k + 3], rhs[6 * k + 4], rhs[6 * k + 5]);
    const double speed = s.v_W[k].norm(), spin = s.w_W[k].norm();
    s.asked_speed_m_per_s = std::max(s.asked_speed_m_per_s, speed);
    s.asked_spin_rad_per_s = std::max(s.asked_spin_rad_per_s, spin);
    if (speed > v_max || spin > w_max) {
      if (speed > v_max) s.v_W[k] *= v_max / speed;
      if (spin > w_max) s.w_W[k] *= w_max / spin;
      ++s.limited_segments;
    }
    s.p_W[k] += dt * s.v_W[k];
    s.R_WS[k] = expSO3(dt * s.w_W[k]) * s.R_WS[k];
    orthonormalize(s.R_WS[k]);
  }
}

// The handle: what the operator applies to keep the outside part on its commanded path
// balances what the last joint applied to it over the step -- the backward-Euler force
// of the solve, f0 + df/dx dt u + df/du (u - u0), with the distal segment's new velocity
// u (after the limits), the one the chain's momentum took. (The joint penalty evaluated
// at the new state instead adds the linearisation error of one step's rotation: a segment
// at the anus tilted 0.5 rad and spun 0.1 rad per step opens the 2e6 N/m joint by ~40 um,
// 80 N on the handle for one step, which the next steps relax.)
void setHandleReaction(const ScopeModel& m, ScopeState& s, const BaseJoint& base, int simulated, double dt) {
  const Vec3 e = m.R_W_entry.col(2);
  const double beta = m.params.joint_damping_s;
  const int j = simulated - 1;
  const Vec6 u_new = stacked(s.v_W[j], s.w_W[j]);
  const Vec6 f_on_base = base.f0 - base.K * ((dt + beta) * u_new - beta * base.u0);
  s.handle.force_W = f_on_base.head<3>();
  s.handle.force_N = -f_on_base.head<3>().dot(e);
  s.handle.torque_Nm = -f_on_base.tail<3>().dot(e);
}

}  // namespace

void advanceScope(const ScopeModel& m, ScopeState& s, const HandleInput& in, double dt, int inside_set,
                  const std::atomic<bool>* wall_speed_ready) {
  // Inputs: the outside part moves with the handle; segments that reach the anus are added
  // to (pushed in) or removed from (withdrawn) the simulated chain.
  const int inside = insideAfter(m, in, inside_set);
  const int simulated = simulatedAfter(m, in, inside);
  const int rejoined = trackTiltedSegment(m, s, simulated);
  moveOutsidePart(m, s, in, simulated, rejoined, dt);
  s.inside = inside;
  s.simulated = simulated;
  s.input = in;
  s.time_s += dt;
  if (simulated == 0) {  // nothing inside: no forces on the handle
    s.handle = HandleReaction();
    s.sphincter_force_W.setZero();
    s.lens_impulse_Ns = 0;
    s.solver_ok = true;
    return;
  }
  // Forces and the system: per segment, per joint, per load, and the sphincter.
  addSegmentTerms(m, s, simulated, dt);
  const BaseJoint base = addJointTerms(m, s, in, simulated, dt);
  addLoadTerms(s, simulated, dt);
  const SphincterLoad ring = addSphincterTerms(m, s, in, inside, simulated, dt);
  // Solve for the velocity change, integrate (with the speed limits), and read the
  // handle's reaction off the last joint.
  solveVelocityChange(s, simulated, dt);
  guardLens(m, s, simulated, dt, wall_speed_ready);
  integrateSegments(m, s, simulated, dt);
  setHandleReaction(m, s, base, simulated, dt);
  // The sphincter's force over the step, which the body takes: handle.force_W
  // is what the scope exerts on the anus and the handle together.
  s.sphincter_force_W = sphincterForceOverStep(s, ring, dt);
  s.handle.force_W -= s.sphincter_force_W;
}

void stepScope(const ScopeModel& m, ScopeState& s, const HandleInput& raw_in, double dt,
               const std::atomic<bool>* wall_speed_ready) {
  // Inputs: the command clamped into the scope's ranges, and where the grip lets the hand
  // take the outside part this step.
  const HandleInput cmd = clampHandleInput(m, raw_in);
  const HandleInput target = gripTarget(m, s, cmd, dt);
  // The step, from a saved start.
  saveStart(s);
  advanceScope(m, s, target, dt, -1, wall_speed_ready);
  if (wall_speed_ready) waitUntilSet(*wall_speed_ready);  // the grip's trials read it too
  // Limit: the grip slips when the step asked for more than it holds (the step is taken
  // again from the start); the slip is kept for catching up.
  holdWithinGrip(m, s, target, dt);
  recordGripSlip(s, cmd);
  // The active scope's actuators (nothing for a passive scope): the lead recorded, the
  // actuated joints' rest bends one lag step towards their targets, within the torque limit.
  updateActiveScope(m, s, s.start.input.insertion_m, dt);
}

double scopeKineticEnergy(const ScopeModel& m, const ScopeState& s) {
  double e = 0;
  for (int k = 0; k < s.simulated; ++k) {
    const Vec3 w_S = s.R_WS[k].transpose() * s.w_W[k];
    e += 0.5 * m.segment_mass_kg * s.v_W[k].squaredNorm() +
         0.5 * w_S.dot(m.segment_inertia_kgm2.cwiseProduct(w_S));
  }
  return e;
}

}  // namespace colosim
