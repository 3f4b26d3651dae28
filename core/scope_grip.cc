#include "core/scope_grip.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/scope_step.h"

namespace colosim {

namespace {

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

HandleInput gripTarget(const ScopeModel& m, const ScopeState& s, const HandleInput& cmd, double dt) {
  const ScopeParams& p = m.params;
  const double max_insertion = (m.segment_count - 1) * m.h_m;
  HandleInput target = cmd;
  const double catch_m = p.grip_catch_up_m_per_s * dt, catch_rad = p.grip_catch_up_rad_per_s * dt;
  if (std::abs(s.grip_slip_m) > catch_m)
    target.insertion_m = std::clamp(cmd.insertion_m - s.grip_slip_m + std::copysign(catch_m, s.grip_slip_m), 0.0,
                                    max_insertion);
  if (std::abs(s.grip_slip_rad) > catch_rad)
    target.rotation_rad = cmd.rotation_rad - s.grip_slip_rad + std::copysign(catch_rad, s.grip_slip_rad);
  return target;
}

void holdWithinGrip(const ScopeModel& m, ScopeState& s, const HandleInput& target, double dt) {
  const ScopeParams& p = m.params;
  const double max_insertion = (m.segment_count - 1) * m.h_m;
  s.asked_handle_force_N = s.handle.force_N;
  s.asked_handle_torque_Nm = s.handle.torque_Nm;
  s.grip_limited = !withinGrip(p, s.handle);
  if (!s.grip_limited) return;
  // The step again from the start with the outside part moved by (dL, dphi) from where it
  // was, keeping the simulated segments of the hand's move (so that the reaction stays
  // affine in the move).
  const double L0 = s.start.input.insertion_m, phi0 = s.start.input.rotation_rad;
  const int inside_hand = s.inside;
  const double want_L = target.insertion_m - L0, want_phi = target.rotation_rad - phi0;
  // The move tried whose reaction lies least beyond the grip (in fractions of its limits),
  // starting with the hand's own move, which asked what the grip could not hold.
  auto excess = [&](const HandleReaction& r) {
    return std::max(std::abs(r.force_N) / p.max_handle_force_N, std::abs(r.torque_Nm) / p.max_handle_torque_Nm);
  };
  double least_dL = want_L, least_dphi = want_phi, least = excess(s.handle);
  if (!std::isfinite(least)) least = std::numeric_limits<double>::infinity();
  auto trial = [&](double dL, double dphi) {
    restoreStart(s);
    HandleInput in = target;
    in.insertion_m = std::clamp(L0 + dL, 0.0, max_insertion);
    in.rotation_rad = phi0 + dphi;
    advanceScope(m, s, in, dt, inside_hand);
    const double e = excess(s.handle);
    if (e < least) least = e, least_dL = dL, least_dphi = dphi;
    return s.handle;
  };
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
  // A force the moves leave beyond the limit (contacts at their own limits do not answer a
  // small move, or the force is beyond it with the tube held still): the tube slides
  // through the fingers, by the move of +-0.1 to +-1.6 mm that brings the force lowest,
  // stopping at the first within the grip.
  if (std::abs(r.force_N) > p.max_handle_force_N && std::isfinite(r.force_N)) {
    double best_dL = dL, best_F = std::abs(r.force_N);
    for (double move_m = 1e-4; move_m <= 1.6e-3 && best_F > p.max_handle_force_N; move_m *= 2)
      for (double sign : {-1.0, 1.0}) {
        const double F = std::abs(trial(dL + sign * move_m, dphi).force_N);
        if (F < best_F) best_F = F, best_dL = dL + sign * move_m;
        if (best_F <= p.max_handle_force_N) break;
      }
    r = trial(best_dL, dphi);
  }
  // Where every move the search made is still beyond the grip, the one that asked the least
  // (when a step's segments meet the speed limit, a move is not answered affinely and the
  // search can end further out than where it began: 2.5 m/s turned from push to pull asked
  // 143 N of the hand and ended at -849 N).
  if (!withinGrip(p, r) && excess(r) > least) trial(least_dL, least_dphi);
}

void recordGripSlip(ScopeState& s, const HandleInput& cmd) {
  s.grip_slip_m = cmd.insertion_m - s.input.insertion_m;
  s.grip_slip_rad = cmd.rotation_rad - s.input.rotation_rad;
}

}  // namespace colosim
