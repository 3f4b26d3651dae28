// The active scope (issue 20, the paper's polyarticulated SMA-driven endoscope): actuated
// joints whose rest bend is commanded. Free functions of the model and state; the scope
// step calls updateActiveScope() once at the end of every step (core/scope_step.cc).
//
// Actuator (per actuated joint k, ScopeState::joint_rest_rad[k], joint frame):
//   rest <- rest + (1 - exp(-dt / tau)) (target - rest)          (first-order lag, exact)
//   then  |K_b (rest - Omega)| <= M_max over the two bending axes (x, y),
// with K_b = EI/h the joint's bending stiffness, Omega = log(R_{k+1}^T R_k) its rotation at
// the step's end and M_max = joint_torque_limit_Nm: the actuator drives the joint through
// the joint's elastic element (series-elastic), so its moment is K_b (rest - Omega); at the
// limit the actuator yields (the rest is pulled back towards Omega) rather than push harder.
// The twist component of the rest stays 0: the actuators bend, they do not twist.
// Within a step the backward-Euler moment uses the step's end rotation with the rest of
// the step's start, so it can exceed M_max by K_b times one step's change of Omega.
//
// Targets (bending components in the joint frame, twist 0):
// - follow-the-leader: the lead is the bend of the tip's joint (joint 0, the knobs' rest
//   rotation in its frame) sampled whenever the insertion passes a multiple j h going in:
//   b(j). Joint k lies at depth L - (k+1) h from the anus, where joint 0 was when the
//   insertion was L - k h, so it takes target = b(L/h - k) (linear between samples, twist 0).
//   The shaft thus repeats, in its own frame, the bends the operator steered the tip
//   through at each depth: in free space it lays itself along the tip's path, and a joint
//   that reaches a depth takes the bend the tip had there. The knobs steer the leader
//   only, joint 0 (its rest is their 1/n share of the bending section, n = bending_joints):
//   the bending section's other joints follow too, or its bend, set at once by the knobs
//   over 9 cm, would swing the tip off the path the shaft then follows (14 mm in the free
//   space test). The tip thus turns as the scope advances, not on the spot. Before any sample (a depth not
//   yet reached) the bend is the first sample's. Withdrawing keeps the record: the joints
//   still follow it; pushing in again re-records what the tip passes. The record is in the
//   scope's frame: turning the handle turns the whole shape with it.
// - contact_minimising (the paper's Figure 12 multi-agent conformation): each joint is an
//   agent that sees the wall contact loads (ScopeState::loads, the step's contact forces)
//   on the n segments each side of it and yields to them: with M_d the moment about the
//   joint of the loads on the distal side (segments k-n+1 .. k) and M_p on the proximal
//   side (k+1 .. k+n), turning the distal side about M_d or the proximal side about M_p
//   moves the contact points along their forces (out of the wall), so the relative
//   rotation yields along Y = R_{k+1}^T (M_d - M_p). The agent keeps moving its target
//   ahead of its rest while the contact moment lasts, and lets it relax to straight
//   (passive) without contact: target = rest + gain Y / K_b - (tau / T_relax) rest, which
//   through the lag is d rest/dt = gain Y / (K_b tau) - rest / T_relax: an integral agent
//   that yields until its neighbourhood's contact moment is gone or its torque is spent.
#pragma once

#include "core/scope_state.h"

namespace colosim {

/// The knobs' rest rotation of joint k through the angulation wires [rad]: the knobs'
/// bend (restJointRotation) while the joint's bending moment K_b |rest - Omega| towards it
/// stays within ScopeParams::knob_moment_limit_Nm (0: no limit), else the rest pulled back
/// towards the joint's present rotation Omega so that the moment is the limit
/// (limitActuatorMoment, K_b = EI/h times the stiffness level's factor). Stateless: a joint
/// the wall lets go returns to the knobs' bend. Joints beyond the bending section: 0.
Vec3 wireLimitedRest(const ScopeModel& m, const ScopeState& s, int k, const HandleInput& in);

/// The rest rotation of joint k the step uses: the actuators' for an actuated joint of an
/// active scope, else the knobs' through the wires (wireLimitedRest) [rad].
inline Vec3 jointRestRotation(const ScopeModel& m, const ScopeState& s, int k, const HandleInput& in) {
  if (k >= m.first_actuated_joint && k < m.actuated_joints) return s.joint_rest_rad[k];
  return wireLimitedRest(m, s, k, in);
}

/// One step of the first-order lag from `rest` towards `target`, time constant tau_s [rad].
Vec3 actuatorLag(const Vec3& rest, const Vec3& target, double dt_s, double tau_s);

/// The rest pulled back towards `omega` so that the bending moment K_b (rest - omega)
/// (x, y components, bending_stiffness = K_b [N m/rad]) is at most limit_Nm; the twist
/// component is set to 0 [rad].
Vec3 limitActuatorMoment(const Vec3& rest, const Vec3& omega, double bending_stiffness_Nm_per_rad,
                         double limit_Nm);

/// The actuator's bending moment on joint k now, |K_b (rest - Omega)| over x, y [N m].
double actuatorMoment(const ScopeModel& m, const ScopeState& s, int k);

/// The lead's bend at the continuous sample index x, linear between samples, clamped to
/// the samples taken [rad].
Vec3 leadBend(const ScopeState& s, double x);

/// Follow-the-leader target of joint k at insertion insertion_m [rad] (joint frame).
Vec3 followTheLeaderTarget(const ScopeModel& m, const ScopeState& s, int k, double insertion_m);

/// Contact-minimising target of joint k [rad] (joint frame) from its rest and
/// distal_moment_W, the moment about the joint of every contact load on the segments distal
/// of it (0..k) [N m]: turning the joint along that moment, with the shaft behind it held,
/// moves those contacts along their forces, out of the wall (the gradient of the contact
/// energy in the joint's angle).
Vec3 contactMinimisingTarget(const ScopeModel& m, const ScopeState& s, int k, const Vec3& distal_moment_W);

/// Samples the lead: for every j with previous_insertion_m < j h <= s.input.insertion_m the
/// tip joint's bend (the knobs'); samples missing below the insertion (a scope placed at
/// depth without being pushed there) are taken from the shaft: sample j from the bend of
/// joint L/h - j, where joint 0 would have been.
void recordLead(const ScopeModel& m, ScopeState& s, double previous_insertion_m);

/// The active scope's end of step: records the lead, then moves every actuated inside
/// joint's rest one lag step towards its strategy's target within the torque limit (the
/// joints outside go straight). Nothing when the scope is passive. Allocates nothing.
void updateActiveScope(const ScopeModel& m, ScopeState& s, double previous_insertion_m, double dt_s);

}  // namespace colosim
