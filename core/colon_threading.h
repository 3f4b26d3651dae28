// The colon held around the scope between the scope's slices (issue 16).
//
// The wall contacts of eq. 7 sample the wall at the scope's interaction points, one ring
// per slice (1.5 cm apart). Between two slices the colon is held only through them. A
// sigmoid gathered onto the scope (1.7 m of colon per m of scope in a 1 m/s withdrawal
// with the tip slammed up) has control points that no slice is at, and a chain with no
// bending stiffness buckles sideways there: the bulge grows into a loop whose two ends lie
// on adjacent slices, and the scope runs straight through its neck, out of the rectum and
// into the sigmoid beside it (variants of extreme_all: 0.36 m track jumps, 177-219 steps
// out of the lumen; docs/hardening.md).
//
// Threading contacts sample the same wall at the colon's own control points. Every
// control point i whose place along the colon lies between the tracks of two consecutive
// slices a and b (anus to tip) has the scope's axis there at y, the point nearest q_i of
// the chain's polyline of slice centres over the chord a-b and its two neighbours (the
// chords into a and out of b). Its distance moves continuously as a track passes a
// control point, and as tracks flip for a step among the control points a gathered colon
// brings within millimetres of one slice (docs/clinical-mechanics.md, session 27). Where
// the scope's surface lies beyond the wall's thickness at that cross-section
//   depth = |y - q_i| - (r_i - r_scope + wall_thickness) > 0,
// what lies behind the wall pushes back: ContactParams::threading_stiffness_N_per_m per
// metre of depth (and the wall's damping and friction), on the scope at y and on the colon
// at q_i, opposite. At the two ends of the chain (the tip, the most proximal slice inside)
// a control point just passed is handed over: its contact's weight grows from 0 to 1 over
// half a control-point spacing of the end slice's further travel. Where the scope is
// inside the lumen nothing is found; pressed into the wall between two slices, a control
// point takes up to a newton or so (sigmoid_untwist: at most 0.5 mm deep).
#pragma once

#include <vector>

#include "core/world.h"

namespace colosim {

/// Appends to `out` the threading contacts of the state's slice tracks (see above): each a
/// WallContact at y on the scope segment of the nearer slice (`point` 0: a slice's
/// scaling), located at control point i (segment i, p = 0), with its normal from q_i
/// towards y, its depth [m] and its weight (1, less where handed over at a chain's end).
/// Control points 1 .. n - 2 only. With margin_m > 0 also the control points within that
/// much of the depth where a contact begins (depth > -margin_m: the stop's candidates).
void findThreadingContacts(const WorldModel& model, const WorldState& state, std::vector<WallContact>& out,
                           double margin_m = 0.0);

/// When ContactParams::threading_stiffness_N_per_m > 0: finds the threading contacts into
/// state.threading and appends their loads to state.colon.loads and state.scope.loads
/// (eq. 7 with the threading stiffness, no backing; the wall's damping, friction and force
/// limit), counting them into state.max_wall_force_N and state.contact_limit; and sets the
/// step's threading stops (stopThreading, below) in state.threading_stops. Otherwise clears
/// both.
/// `previous`: a previous sweep's end (ContactParams::coupling_sweeps, applyWallContacts).
void applyThreadingContacts(const WorldModel& model, WorldState& state, double dt_s,
                            const CouplingSweep* previous = nullptr);

/// The threading stop, after both bodies' steps. A penalty found at the start of a step
/// cannot hold a control point that the scope closes on faster than its depth allows in
/// one step: in the abuse scripts on the folded candidate patient (docs/clinical-mechanics.md,
/// session 28) threading contacts appeared from nothing 0.7-2 mm beyond the wall's thickness,
/// the scope's slice moving at 1-3 m/s, and asked 20-52 N, over the force limit (which then
/// scales the force down: a solver limit). So every control point within a step at the
/// scope's speed limit of a contact (findThreadingContacts with that margin), of weight w > 0,
/// is also a unilateral stop at the velocity level, as the lens guard is for the lens
/// (core/scope_step.cc) but on both bodies: where the two solved velocities take it deeper
/// within the step than the depth at which its spring asks ContactParams::threading_stop_force_N
/// (0.33 mm / w at 10 N and 30,000 N/m; or than it was, if deeper), an impulse P stops it there, shared as
/// in an inelastic contact:
///   P (J_c A_c^-1 J_c^T + J_s A_s^-1 J_s^T) = (depth + dt (v_s - v_c) . n - allowed) / dt
/// with each body's step matrix A (its factors, kept from the step) and J the point along
/// the contact's normal n (the control point; the axis point on its scope segment). The
/// colon's velocities and positions move by P A_c^-1 J_c^T, the scope's by -P A_s^-1 J_s^T
/// (the rotations by the exponential). Two passes in order (the second only after a first
/// that engaged), impulses only added: deterministic. Limits: the handle's reaction, the
/// speed limits and the tension laws' history are the step's, before the stop; the axis
/// point is the one found at the start of the step, carried by its segment's velocity.
void stopThreading(const WorldModel& model, WorldState& state, double dt_s);

}  // namespace colosim
