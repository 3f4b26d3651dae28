// Abdominal pressure: an assistant's hand pressing on the abdomen over a mobile segment of
// the colon (the sigmoid, the transverse colon) so that it does not bow out under the
// scope, a standard manoeuvre when loops take up the push (Bruce & Choi 2018; the
// scenario's abdominal_pressure, docs/file-formats.md). Not in the paper.
//
// The hand is modelled as extra lifters on the pressed region that hold it where it lay
// when the pressing began: over the region's spline segments a force density -k u - c v at
// each spline point displaced u = M(s) - A(s) from its anchor A (the spline through the
// control points as they were at that moment) and moving at v = dM/dt (eqs. 4-5 with the
// pressure's own k and c and the anchor for the rest shape), integrated by 4-point Gauss
// quadrature over each segment like the mesentery's K and C, and applied as spline loads
// (their stiffness and damping enter the implicit solve, so the step stays unconditionally
// stable for any k). The hand holds the segment in every direction: a simplification of a
// hand that only pushes (it keeps a loop from bowing further out, it does not pull).
// Anchoring at the rest shape instead pulled a transverse colon the scope had straightened
// back into its hanging U, and the tip back out of the ascending colon (free_insertion).
#pragma once

#include <vector>

#include "core/colon_model.h"
#include "core/colon_state.h"

namespace colosim {

/// One pressed region during one step: spline segments [first_segment, last_segment] of
/// the colon, with the densities in force this step (already ramped by the caller).
struct RegionSupport {
  int first_segment = 0;
  int last_segment = -1;            ///< inclusive; last < first: nothing pressed
  double stiffness_N_per_m2 = 0;    ///< k [N/m per m], >= 0 (0: not pressing this step)
  double damping_Ns_per_m2 = 0;     ///< c [N s/m per m], >= 0
  Points anchor_q;                  ///< all control points when the pressing began (3 x n); empty: not yet
};

/// Appends the support's loads to `loads`: 4 per segment (the Gauss points), force
/// -w (k u + c v), stiffness w k I, damping w c I, w the Gauss weight times the segment's
/// rest arclength. Nothing when k and c are both zero or there is no anchor (anchor_q must
/// otherwise have the model's n columns: std::invalid_argument). Segments are clamped to
/// the colon.
void addRegionSupport(const ColonModel& model, const ColonState& state, const RegionSupport& support,
                      std::vector<SplineLoad>& loads);

/// The ramp of a pressure applied over [from_s, to_s] [s]: 0 outside, rising linearly to 1
/// over ramp_s after from_s and falling to 0 over ramp_s before to_s (the smaller of the
/// two ramps when they overlap); a step when ramp_s is 0.
double pressureRamp(double t_s, double from_s, double to_s, double ramp_s);

}  // namespace colosim
