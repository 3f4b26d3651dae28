#include "core/scope_step.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "core/rotation.h"

namespace colosim {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

ScopeState makeScopeState(const ScopeModel& m, int load_capacity) {
  ScopeState s;
  const int K = m.segment_count;
  s.p_W.resize(K);
  s.R_WS.resize(K);
  s.v_W.assign(K, Vec3::Zero());
  s.w_W.assign(K, Vec3::Zero());
  for (int k = 0; k < K; ++k) kinematicPose(m, k, 0.0, 0.0, &s.p_W[k], &s.R_WS[k]);
  s.inside = 0;
  s.loads.reserve(load_capacity);
  s.system.resize(K);
  s.rhs = Eigen::VectorXd::Zero(6 * K);
  s.force = Eigen::VectorXd::Zero(6 * K);
  s.start.p_W = s.p_W;
  s.start.R_WS = s.R_WS;
  s.start.v_W = s.v_W;
  s.start.w_W = s.w_W;
  return s;
}

void kinematicPose(const ScopeModel& m, int k, double L, double phi, Vec3* p, Mat3* R) {
  const Vec3 e = m.R_W_entry.col(2);
  const double s_centre = (k + 0.5) * m.h_m;
  *p = m.p_W_anus + (L - s_centre) * e;
  *R = expSO3(phi * e) * m.R_W_entry;
}

void exitPose(const ScopeModel& m, int k, double L, double phi, const Vec3& tilt_rad, Vec3* p, Mat3* R) {
  const Vec3 e = m.R_W_entry.col(2);
  const double out = std::clamp(((k + 1) * m.h_m - L) / m.h_m, 0.0, 1.0);  // fraction of its length outside
  *R = expSO3((1.0 - out) * tilt_rad) * expSO3(phi * e) * m.R_W_entry;
  *p = m.p_W_anus + (L - (k + 0.5) * m.h_m) * R->col(2);
}

HandleInput clampHandleInput(const ScopeModel& m, const HandleInput& in) {
  auto finite = [](double x) { return std::isfinite(x) ? x : 0.0; };
  HandleInput c;
  const double max_insertion = (m.segment_count - 1) * m.h_m;
  c.insertion_m = std::clamp(finite(in.insertion_m), 0.0, max_insertion);
  c.rotation_rad = finite(in.rotation_rad);
  c.knob_updown_rad = std::clamp(finite(in.knob_updown_rad), -kKnobUpDownMax_rad, kKnobUpDownMax_rad);
  c.knob_leftright_rad =
      std::clamp(finite(in.knob_leftright_rad), -kKnobLeftRightMax_rad, kKnobLeftRightMax_rad);
  return c;
}

Vec3 tipPosition(const ScopeModel& m, const ScopeState& s) {
  return s.p_W[0] + 0.5 * m.h_m * s.R_WS[0].col(2);
}

Mat3 tipFrame(const ScopeState& s) { return s.R_WS[0]; }

Vec3 restJointRotation(const ScopeModel& m, int joint, const HandleInput& in) {
  if (joint >= m.bending_joints) return Vec3::Zero();
  // Up bends d3 towards d2: a rotation about d1 by -angle. Right bends d3 towards the
  // image's right, -d1: a rotation about d2 by -angle.
  const double n = m.bending_joints;
  return Vec3(-in.knob_updown_rad / n, -in.knob_leftright_rad / n, 0.0);
}

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
  const double h = m.h_m;
  const Vec3 d3k = s.R_WS[k].col(2), d3p = s.R_WS[k + 1].col(2);
  // Position: the distal segment's proximal end meets the proximal segment's distal end.
  // gap rate = Jd u_k + Jp u_{k+1} with Jd = [I, Sd], Jp = [-I, Sp], S = (h/2)[d3]x.
  const Vec3 gap = (s.p_W[k] - 0.5 * h * d3k) - (s.p_W[k + 1] + 0.5 * h * d3p);
  const Mat3 Sd = 0.5 * h * skew(d3k), Sp = 0.5 * h * skew(d3p);
  const double kj = m.params.joint_stiffness_N_per_m;
  const Vec3 gap_rate = s.v_W[k] + Sd * s.w_W[k] - s.v_W[k + 1] + Sp * s.w_W[k + 1];
  const Vec3 fg = kj * (gap + m.params.joint_damping_s * gap_rate);

  // Rotation: bending and torsion against the rest rotation.
  const Mat3 R_rel = s.R_WS[k + 1].transpose() * s.R_WS[k];
  const Vec3 omega = logSO3(R_rel);
  const Vec3 err = omega - restJointRotation(m, k, in);
  const Mat3 A = rightJacobianInverse(omega) * s.R_WS[k].transpose();
  const Vec3 rel_rate = A * (s.w_W[k] - s.w_W[k + 1]);
  const Vec3& kd = m.joint_stiffness_Nm_per_rad;
  const Vec3 moment = kd.cwiseProduct(err + m.params.joint_damping_s * rel_rate);  // joint frame
  const Vec3 tau = A.transpose() * moment;  // world torque on the distal segment is -tau

  JointTerms t;
  // Generalised forces -J^T fg (J^T = [I; S^T] with S^T = -S), plus the rotational moment.
  t.f_distal << -fg, Sd * fg - tau;
  t.f_proximal << fg, Sp * fg + tau;
  // Gauss-Newton stiffness kj J^T J from 3x3 pieces, plus A^T K A on the rotations.
  const Mat3 AKA = A.transpose() * kd.asDiagonal() * A;
  const Mat3 I3 = Mat3::Identity();
  t.K_dd << kj * I3, kj * Sd, -kj * Sd, -kj * Sd * Sd + AKA;
  t.K_pp << kj * I3, -kj * Sp, kj * Sp, -kj * Sp * Sp + AKA;
  t.K_dp << -kj * I3, kj * Sp, kj * Sd, -kj * Sd * Sp - AKA;
  return t;
}

// The step with the outside part taken to `in` (clamped): everything but the grip.
// `inside` >= 0 sets the simulated segments instead of the insertion (the grip's trials
// keep those of the hand's move, so that the reaction stays affine in the move).
void advance(const ScopeModel& m, ScopeState& s, const HandleInput& in, double dt, int inside_set = -1) {
  const int K = m.segment_count;
  const double h = m.h_m;
  const Vec3 e = m.R_W_entry.col(2);
  const double insertion_rate = (in.insertion_m - s.input.insertion_m) / dt;
  const double rotation_rate = (in.rotation_rad - s.input.rotation_rad) / dt;

  // Inputs: the part outside moves with the handle; segments that crossed the anus are
  // added to (pushed in) or removed from (withdrawn) the simulated chain.
  const int inside =
      inside_set >= 0 ? inside_set : std::min(K - 1, static_cast<int>(std::floor(in.insertion_m / h + 1e-9)));
  // A segment withdrawn out of the chain keeps the tilt the chain gave it and comes out
  // pivoting about the anus, straightening as it does (exitPose). Put straight at once, a
  // segment bent 0.17 rad at the anus opened the last joint by 2.5 mm in one step, a pull
  // kick of 35-46 N on the handle at each crossing of a hooked withdrawal.
  // (Invariant: tilted_segment is -1 or the first outside segment, s.inside.)
  int rejoined = -1;  // the tilted segment, pushed back in before it came out: it rejoins as it is
  if (inside < s.inside) {
    Vec3 p;
    Mat3 R_straight;
    kinematicPose(m, inside, in.insertion_m, in.rotation_rad, &p, &R_straight);
    s.tilted_segment = inside;
    s.tilt_rad = logSO3(s.R_WS[inside] * R_straight.transpose());
  } else if (inside > s.inside) {
    rejoined = s.tilted_segment;
    s.tilted_segment = -1;
  }
  // A segment that crosses the anus this step joins from where it was at the start of the
  // step (its kinematic pose of the last inputs) with the handle's velocity, like the
  // simulated segments: the integration below carries it on. (Placed at the new inputs'
  // pose and then integrated, it ran dt * speed ahead of its base: 0.7 mm at 1 m/s, which
  // the 2e6 N/m joint read as a pull of up to 495 N on the handle in extreme_all.)
  for (int k = std::min(inside, s.inside); k < K; ++k) {
    if (k < inside && k < s.inside) continue;
    if (k == rejoined) continue;  // keeps its pose and the velocity it came out with
    if (k == s.tilted_segment) {
      // The velocity of its move this step, for the joint's damping.
      const Vec3 p0 = s.p_W[k];
      const Mat3 R0 = s.R_WS[k];
      exitPose(m, k, in.insertion_m, in.rotation_rad, s.tilt_rad, &s.p_W[k], &s.R_WS[k]);
      s.v_W[k] = (s.p_W[k] - p0) / dt;
      s.w_W[k] = logSO3(s.R_WS[k] * R0.transpose()) / dt;
      continue;
    }
    if (k >= inside) kinematicPose(m, k, in.insertion_m, in.rotation_rad, &s.p_W[k], &s.R_WS[k]);
    s.v_W[k] = insertion_rate * e;
    s.w_W[k] = rotation_rate * e;
  }
  // A segment that has just crossed the anus joins the chain pre-relaxed: turned by half of
  // its distal neighbour's joint rotation (where the bending moment would put it) and
  // hanging from the outside part's distal end, so that it does not swing into place
  // (a spurious kick on the handle force).
  for (int k = std::max(s.inside, 1); k < inside; ++k) {
    if (k == rejoined) continue;
    const Vec3 half = 0.5 * logSO3(s.R_WS[k].transpose() * s.R_WS[k - 1]);
    const Vec3 joint_W = s.p_W[k] - 0.5 * h * s.R_WS[k].col(2);  // proximal end: fixed
    s.R_WS[k] = s.R_WS[k] * expSO3(half);
    s.p_W[k] = joint_W + 0.5 * h * s.R_WS[k].col(2);
  }
  // The tip joins bent as the knobs hold it (at its joint's rest rotation), or it is
  // flung by the whole bending moment at once (0.7 N m on 3 g with the knobs at a stop).
  if (s.inside == 0 && inside > 0 && rejoined != 0) {
    const Vec3 joint_W = s.p_W[0] - 0.5 * h * s.R_WS[0].col(2);
    s.R_WS[0] = s.R_WS[0] * expSO3(restJointRotation(m, 0, in));
    s.p_W[0] = joint_W + 0.5 * h * s.R_WS[0].col(2);
  }
  s.inside = inside;
  s.input = in;
  s.time_s += dt;
  if (inside == 0) {
    s.handle = HandleReaction();
    s.solver_ok = true;
    return;
  }

  // Forces and the system, per segment then per joint then per load.
  const int n = 6 * inside;
  double* f = s.force.data();
  double* rhs = s.rhs.data();
  std::fill(f, f + n, 0.0);
  std::fill(rhs, rhs + n, 0.0);
  s.system.setZero(inside);
  const double drag = m.params.drag_Ns_per_m2 * h;
  for (int k = 0; k < inside; ++k) {
    Mat6 Mk = Mat6::Zero();
    Mk.topLeftCorner<3, 3>() = (m.segment_mass_kg + dt * drag) * Mat3::Identity();
    Mk.bottomRightCorner<3, 3>() =
        s.R_WS[k] * m.segment_inertia_kgm2.asDiagonal() * s.R_WS[k].transpose();
    s.system.diag(k) += Mk;
    const Vec3 fk = m.segment_mass_kg * m.gravity_m_per_s2 - drag * s.v_W[k];
    for (int c = 0; c < 3; ++c) f[6 * k + c] += fk(c);
  }

  const double beta = m.params.joint_damping_s;
  Vec6 base_f0 = Vec6::Zero(), base_u0 = Vec6::Zero();  // the last joint's force on the base, the distal segment's velocity, at the start
  Mat6 base_K = Mat6::Zero();  // the last joint's stiffness block (base row, distal segment column)
  const double sys_k = dt * beta + dt * dt;  // dt C + dt^2 K with C = beta K
  for (int k = 0; k < inside; ++k) {  // joint k joins segment k and k+1 (k+1 == inside: the base)
    const JointTerms t = jointTerms(m, s, k, in);
    const bool proximal_simulated = (k + 1 < inside);
    const Vec6 uk = stacked(s.v_W[k], s.w_W[k]);
    if (!proximal_simulated) base_f0 = t.f_proximal, base_K = t.K_dp.transpose(), base_u0 = uk;
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

  for (const ScopeLoad& load : s.loads) {
    if (load.segment < 0 || load.segment >= inside) continue;
    // Point velocity v + w x r = J u with J = [I, -[r]x]; J^T = [I; [r]x].
    const int k = load.segment;
    const Mat3 Rx = skew(load.r_W);
    const Vec3 v_point = s.v_W[k] + s.w_W[k].cross(load.r_W);
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

  // Solve (M + dt C + dt^2 K) du = dt f - dt^2 K u on the simulated segments: a block
  // tridiagonal system (6 x 6 blocks), by block Cholesky.
  for (int i = 0; i < n; ++i) rhs[i] += dt * f[i];
  s.limited_segments = 0;
  s.asked_speed_m_per_s = s.asked_spin_rad_per_s = 0;
  s.solver_ok = s.system.factorize(inside);
  if (s.solver_ok) {
    s.system.solveInPlace(inside, rhs);
    for (int i = 0; i < n; ++i) s.solver_ok = s.solver_ok && std::isfinite(rhs[i]);
  }
  if (!s.solver_ok) std::fill(rhs, rhs + n, 0.0);  // limit: the segments stop (below) rather than carry NaN on

  // Integrate the simulated segments; limit: a segment faster than the solve is trusted
  // with is slowed to that speed or spin.
  const double v_max = m.params.max_speed_m_per_s, w_max = m.params.max_spin_rad_per_s;
  for (int k = 0; k < inside; ++k) {
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

  // The handle: what the operator applies to keep the outside part on its commanded path
  // balances what the last joint applied to it over the step -- the backward-Euler force
  // of the solve, f0 + df/dx dt u + df/du (u - u0), with the distal segment's new velocity
  // u (after the limits), the one the chain's momentum took. (The joint penalty evaluated
  // at the new state instead adds the linearisation error of one step's rotation: a segment
  // at the anus tilted 0.5 rad and spun 0.1 rad per step opens the 2e6 N/m joint by ~40 um,
  // 80 N on the handle for one step, which the next steps relax.)
  const int j = inside - 1;
  const Vec6 u_new = stacked(s.v_W[j], s.w_W[j]);
  const Vec6 f_on_base = base_f0 - base_K * ((dt + beta) * u_new - beta * base_u0);
  s.handle.force_W = f_on_base.head<3>();
  s.handle.force_N = -f_on_base.head<3>().dot(e);
  s.handle.torque_Nm = -f_on_base.tail<3>().dot(e);
}

void saveStart(ScopeState& s) {
  ScopeState::Start& a = s.start;
  std::copy(s.p_W.begin(), s.p_W.end(), a.p_W.begin());
  std::copy(s.R_WS.begin(), s.R_WS.end(), a.R_WS.begin());
  std::copy(s.v_W.begin(), s.v_W.end(), a.v_W.begin());
  std::copy(s.w_W.begin(), s.w_W.end(), a.w_W.begin());
  a.inside = s.inside;
  a.tilted_segment = s.tilted_segment;
  a.tilt_rad = s.tilt_rad;
  a.input = s.input;
  a.time_s = s.time_s;
}

void restoreStart(ScopeState& s) {
  const ScopeState::Start& a = s.start;
  std::copy(a.p_W.begin(), a.p_W.end(), s.p_W.begin());
  std::copy(a.R_WS.begin(), a.R_WS.end(), s.R_WS.begin());
  std::copy(a.v_W.begin(), a.v_W.end(), s.v_W.begin());
  std::copy(a.w_W.begin(), a.w_W.end(), s.w_W.begin());
  s.inside = a.inside;
  s.tilted_segment = a.tilted_segment;
  s.tilt_rad = a.tilt_rad;
  s.input = a.input;
  s.time_s = a.time_s;
}

bool withinGrip(const ScopeParams& p, const HandleReaction& r, double fraction = 1.0) {
  return !(std::abs(r.force_N) > fraction * p.max_handle_force_N) &&
         !(std::abs(r.torque_Nm) > fraction * p.max_handle_torque_Nm);
}

// The move x (from the start) that keeps y(x) = y0 + slope x within +-limit, nearest
// `wanted` (a Coulomb grip: the tube slides either way through the fingers); held still
// when the slope is not positive (pushing further must push harder).
double moveWithin(double wanted, double y0, double slope, double limit) {
  if (!(slope > 0) || !std::isfinite(y0)) return 0.0;
  return std::clamp(wanted, (-limit - y0) / slope, (limit - y0) / slope);
}

}  // namespace

void stepScope(const ScopeModel& m, ScopeState& s, const HandleInput& raw_in, double dt) {
  const HandleInput cmd = clampHandleInput(m, raw_in);
  const ScopeParams& p = m.params;
  const double max_insertion = (m.segment_count - 1) * m.h_m;
  // Inputs: where the hand takes the outside part this step. Exactly the command unless
  // the grip has slipped; then the command's own motion plus a bounded catch-up of the slip.
  HandleInput target = cmd;
  const double catch_m = p.grip_catch_up_m_per_s * dt, catch_rad = p.grip_catch_up_rad_per_s * dt;
  if (std::abs(s.grip_slip_m) > catch_m)
    target.insertion_m = std::clamp(cmd.insertion_m - s.grip_slip_m + std::copysign(catch_m, s.grip_slip_m), 0.0,
                                    max_insertion);
  if (std::abs(s.grip_slip_rad) > catch_rad)
    target.rotation_rad = cmd.rotation_rad - s.grip_slip_rad + std::copysign(catch_rad, s.grip_slip_rad);

  saveStart(s);
  advance(m, s, target, dt);
  s.asked_handle_force_N = s.handle.force_N;
  s.asked_handle_torque_Nm = s.handle.torque_Nm;
  s.grip_limited = !withinGrip(p, s.handle);
  if (s.grip_limited) {
    // Limit: the grip slips. The handle reaction is nearly affine in the outside part's
    // move over one step (the joint penalty through one linear solve): measured with the
    // outside part held still and with small probe moves, the move that keeps the force
    // and torque at 99 % of the limits (nearest the hand's) is solved for and the step
    // taken again from the start with it, refined by secant steps if the reaction was
    // not quite affine. Up to 8 steps in all, only while the grip slips.
    const double L0 = s.start.input.insertion_m, phi0 = s.start.input.rotation_rad;
    const int inside_hand = s.inside;
    auto trial = [&](double dL, double dphi) {
      restoreStart(s);
      HandleInput in = target;
      in.insertion_m = std::clamp(L0 + dL, 0.0, max_insertion);
      in.rotation_rad = phi0 + dphi;
      advance(m, s, in, dt, inside_hand);
      return s.handle;
    };
    const double want_L = target.insertion_m - L0, want_phi = target.rotation_rad - phi0;
    const double probe_m = 1e-5, probe_rad = 1e-4;  // small enough to stay affine
    const HandleReaction held = trial(0, 0);
    const double F0 = held.force_N, T0 = held.torque_Nm;
    double slope_F = (trial(probe_m, 0).force_N - F0) / probe_m;
    double slope_T = (trial(0, probe_rad).torque_Nm - T0) / probe_rad;
    const double F_lim = 0.99 * p.max_handle_force_N, T_lim = 0.99 * p.max_handle_torque_Nm;
    double dL = moveWithin(want_L, F0, slope_F, F_lim), dphi = moveWithin(want_phi, T0, slope_T, T_lim);
    HandleReaction r = trial(dL, dphi);
    for (int iter = 0; iter < 3 && !withinGrip(p, r) && std::isfinite(r.force_N) && std::isfinite(r.torque_Nm); ++iter) {
      if (std::abs(dL) > 1e-12) slope_F = (r.force_N - F0) / dL;
      if (std::abs(dphi) > 1e-12) slope_T = (r.torque_Nm - T0) / dphi;
      dL = moveWithin(want_L, F0, slope_F, F_lim);
      dphi = moveWithin(want_phi, T0, slope_T, T_lim);
      r = trial(dL, dphi);
    }
  }
  s.grip_slip_m = cmd.insertion_m - s.input.insertion_m;
  s.grip_slip_rad = cmd.rotation_rad - s.input.rotation_rad;
}

double scopeKineticEnergy(const ScopeModel& m, const ScopeState& s) {
  double e = 0;
  for (int k = 0; k < s.inside; ++k) {
    const Vec3 w_S = s.R_WS[k].transpose() * s.w_W[k];
    e += 0.5 * m.segment_mass_kg * s.v_W[k].squaredNorm() +
         0.5 * w_S.dot(m.segment_inertia_kgm2.cwiseProduct(w_S));
  }
  return e;
}

namespace {
constexpr size_t kSnapshotHeader = 12;  // time, inside, tilted segment, tilt (3), inputs (4), grip slip (2)
}  // namespace

std::vector<double> getScopeState(const ScopeState& s) {
  std::vector<double> out;
  const size_t K = s.p_W.size();
  out.reserve(kSnapshotHeader + K * 18);
  out.push_back(s.time_s);
  out.push_back(s.inside);
  out.push_back(s.tilted_segment);
  out.insert(out.end(), s.tilt_rad.data(), s.tilt_rad.data() + 3);
  out.push_back(s.input.insertion_m);
  out.push_back(s.input.rotation_rad);
  out.push_back(s.input.knob_updown_rad);
  out.push_back(s.input.knob_leftright_rad);
  out.push_back(s.grip_slip_m);
  out.push_back(s.grip_slip_rad);
  for (size_t k = 0; k < K; ++k) {
    out.insert(out.end(), s.p_W[k].data(), s.p_W[k].data() + 3);
    out.insert(out.end(), s.R_WS[k].data(), s.R_WS[k].data() + 9);
    out.insert(out.end(), s.v_W[k].data(), s.v_W[k].data() + 3);
    out.insert(out.end(), s.w_W[k].data(), s.w_W[k].data() + 3);
  }
  return out;
}

void setScopeState(const std::vector<double>& snap, ScopeState& s) {
  const size_t K = s.p_W.size();
  if (snap.size() != kSnapshotHeader + K * 18)
    throw std::invalid_argument("scope state snapshot has " + std::to_string(snap.size()) +
                                " values, expected " + std::to_string(kSnapshotHeader + K * 18));
  size_t i = 0;
  s.time_s = snap[i++];
  s.inside = static_cast<int>(snap[i++]);
  s.tilted_segment = static_cast<int>(snap[i++]);
  std::memcpy(s.tilt_rad.data(), &snap[i], 3 * sizeof(double)); i += 3;
  s.input.insertion_m = snap[i++];
  s.input.rotation_rad = snap[i++];
  s.input.knob_updown_rad = snap[i++];
  s.input.knob_leftright_rad = snap[i++];
  s.grip_slip_m = snap[i++];
  s.grip_slip_rad = snap[i++];
  for (size_t k = 0; k < K; ++k) {
    std::memcpy(s.p_W[k].data(), &snap[i], 3 * sizeof(double)); i += 3;
    std::memcpy(s.R_WS[k].data(), &snap[i], 9 * sizeof(double)); i += 9;
    std::memcpy(s.v_W[k].data(), &snap[i], 3 * sizeof(double)); i += 3;
    std::memcpy(s.w_W[k].data(), &snap[i], 3 * sizeof(double)); i += 3;
  }
}

}  // namespace colosim
