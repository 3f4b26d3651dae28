// The grip: the operator's fingers hold the tube by friction. When the handle force or
// torque a step asks for exceeds model.params.max_handle_force_N or max_handle_torque_Nm,
// the tube slips through the fingers: the outside part moves only as far as keeps the
// reaction at 99 % of the limits, and the slip (command minus actual insertion and
// rotation) is caught up later at grip_catch_up_m_per_s, _rad_per_s. The three stages of
// stepScope() that make the grip, in order.
#pragma once

#include "core/scope_state.h"

namespace colosim {

/// Inputs: where the hand takes the outside part this step. Exactly the (clamped) command
/// `cmd` unless the grip has slipped; then the command's own motion plus a bounded
/// catch-up of the slip (grip_catch_up_m_per_s dt, grip_catch_up_rad_per_s dt).
HandleInput gripTarget(const ScopeModel& model, const ScopeState& state, const HandleInput& cmd, double dt_s);

/// Limit, after the step to `target` from state.start (saveStart()): records the handle
/// reaction that step asked for (state.asked_handle_force_N, _torque_Nm) and whether it is
/// beyond the grip (state.grip_limited); if so, takes the step again from the start with the
/// outside part's move that keeps the reaction within 99 % of the limits, nearest the
/// hand's: solved from the reaction held still and at two small probe moves (the reaction
/// is nearly affine in the move over one step), then refined by secant steps while it is
/// still beyond. Up to 8 steps in all, only while the grip slips; a force the moves leave
/// beyond the limit (contacts at their own limits do not answer a small move) then slides
/// the tube by the move of +-0.1 to +-1.6 mm that brings it lowest (up to 11 more steps).
/// If it is still beyond the grip, the move tried (the hand's own included) whose reaction
/// lay least beyond the limits is taken (one more step): the grip never ends further out
/// than the hand's move asked.
void holdWithinGrip(const ScopeModel& model, ScopeState& state, const HandleInput& target, double dt_s);

/// Records the grip's slip after the step: the command `cmd` minus the outside part's
/// actual insertion and rotation (state.grip_slip_m, state.grip_slip_rad).
void recordGripSlip(ScopeState& state, const HandleInput& cmd);

}  // namespace colosim
