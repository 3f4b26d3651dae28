// One time step of the colonoscope: linearised backward Euler on the segment chain.
// The step's pipeline is stepScope() (grip stages in core/scope_grip.h) around
// advanceScope() (inputs, joining segments, forces, solve, integrate, handle reaction).
//
// Unknowns: the velocity and angular velocity of every simulated segment (6 each): the
// segments inside the body and the one straddling the anus, which the sphincter (a ring,
// ScopeParams::sphincter_stiffness_N_per_m) holds laterally where it crosses the anus;
// the rest, outside, move with the handle. Forces: gravity, drag, the joints (a stiff penalty keeping consecutive segments joined, and
// bending/torsion springs on the relative rotation Omega = log(R_{k+1}^T R_k) against
// the rest rotation set by the knobs in the steerable tip), and the loads (contacts).
// The system (M + dt C + dt^2 K) du = dt (f - dt K u) is banded (a joint couples two
// consecutive segments) and solved by band Cholesky; stiffness uses the Gauss-Newton
// part of each term, which keeps the matrix positive definite. Stable at dt = 1 ms
// although the fastest bending mode of 1 cm segments is ~1.4e4 rad/s (docs/numerics.md).
#pragma once

#include <atomic>

#include "core/scope_state.h"

namespace colosim {

/// Advances the scope by dt_s with the handle inputs `in` (clamped): updates the
/// kinematic part outside the patient, adds or removes simulated segments at the anus,
/// integrates the simulated part with state.loads and the sphincter, and computes
/// state.handle. Allocates nothing.
/// Limits (docs/hardening.md): a segment whose new speed or spin exceeds
/// model.params.max_speed_m_per_s or max_spin_rad_per_s is slowed to it (counted in
/// state.limited_segments); a failed factorisation or a non-finite solve sets
/// state.solver_ok = false and stops the inside segments for the step (no NaN carried on).
/// The grip: when the handle force or torque would exceed model.params.max_handle_force_N
/// or max_handle_torque_Nm, the outside part moves only as far as keeps them at 99 % of
/// the limits (the step is taken again from its start, up to 8 times); the command minus
/// the actual insertion and rotation is kept in state.grip_slip_m, _rad and caught up at
/// grip_catch_up_m_per_s, _rad_per_s; state.grip_limited says so, asked_handle_force_N
/// and asked_handle_torque_Nm what the command asked. state.handle is the backward-Euler
/// force of the last joint on the outside part over the step.
/// `wall_speed_ready`: when the lens wall's speed over the step (state.lens_wall.
/// wall_speed_m_per_s) is being computed on another thread during this step (the world
/// step's two lanes, core/world.cc), a flag that thread sets once it is written; the lens
/// guard waits for it before reading the speed. nullptr: the speed is already set.
void stepScope(const ScopeModel& model, ScopeState& state, const HandleInput& in, double dt_s,
               const std::atomic<bool>* wall_speed_ready = nullptr);

/// The step with the outside part taken to `in` (already clamped and gripped): everything
/// of stepScope() but the grip. `inside_set` >= 0 sets the number of segments inside
/// (and so of the simulated ones) instead of the insertion (the grip's trials keep those of the hand's move, so that the
/// reaction stays affine in the move). Allocates nothing.
void advanceScope(const ScopeModel& model, ScopeState& state, const HandleInput& in, double dt_s,
                  int inside_set = -1, const std::atomic<bool>* wall_speed_ready = nullptr);

/// Kinetic energy and elastic energy of the joints [J] (for tests).
double scopeKineticEnergy(const ScopeModel& model, const ScopeState& state);

}  // namespace colosim
