// One time step of the colon: linearised backward Euler with a banded solve.
//
// Why implicit: with 1-2 cm control-point spacing the tension springs (EA / l ~ 2e3 N/m
// on ~6 g per point, and up to ~3e4 N/m with a whole-tube EA) and the wall contacts put
// the fastest modes near or beyond the explicit stability limit dt < 2 / omega_max at
// dt = 1 ms (../shared/reference/numerics.md; docs/numerics.md). Backward Euler is
// unconditionally stable for these linearised forces, damps only the fast modes
// noticeably at 1 kHz, and its matrix M + dt C + dt^2 K is a block band (control points
// couple at most 3 apart) solved in O(n) by a band Cholesky.
//
// The step solves, with f, K = -df/dq and C = -df/dv taken at the start of the step,
//   (M + dt C + dt^2 K) dv = dt (f - dt K v),   v += dv,   q += dt v
// (one Newton iteration of backward Euler: a fixed amount of work, deterministic).
#pragma once

#include "core/colon_model.h"
#include "core/colon_state.h"

namespace colosim {

/// Advances `state` by dt_s [s]: gravity, mesentery lifters, tension elements, the
/// extensions of colon_extensions.h when the model switches them on, and the loads in
/// state.loads. Allocates nothing. Leaves state.loads untouched (callers
/// clear them).
/// Limits (docs/hardening.md): a control point whose new speed exceeds
/// model.max_speed_m_per_s is slowed to it (counted in state.limited_points). When the
/// factorisation fails (never expected: the matrix is SPD by construction) or the solve
/// gives a non-finite velocity change, state.solver_ok = false, q stays, v is set to zero
/// (the colon stops rather than carry NaN on) and time advances.
void stepColon(const ColonModel& model, ColonState& state, double dt_s);

/// Energies of the colon [J].
struct ColonEnergy {
  double kinetic_J = 0;     ///< v^T M v / 2
  double mesentery_J = 0;   ///< (q - q0)^T K (q - q0) / 2, plus the stiffening part when on
  double tension_J = 0;     ///< sum over elements of l0 * stored energy density
  double gravity_J = 0;     ///< -sum_i m_i g . q_i (zero at the origin)
  double bending_J = 0;     ///< sum of the bending energies at interior control points (0 when off)
  double total() const { return kinetic_J + mesentery_J + tension_J + gravity_J + bending_J; }
};
ColonEnergy colonEnergy(const ColonModel& model, const ColonState& state);

/// Strain [-] and strain rate [1/s] of tension element e (between q_e and q_{e+1}).
void elementStrain(const ColonModel& model, const ColonState& state, int e, double* strain,
                   double* strain_rate);

}  // namespace colosim
