// Whether the scope is where the contact model says it is: inside the colon's lumen, each
// slice tracked on the part of the colon it is really in (the contact topology). Measured
// on a world state after a step, for the run summary, the scores and the tests; nothing
// here changes the state.
//
// A slice's track is the spline location of its centre (state.slice_track);
// arclength is along the present centreline, summed over the chords between control points
// (1.5 cm apart: within a few per cent of the curve's own length at the bends the colon takes).
#pragma once

#include <vector>

#include "core/world.h"

namespace colosim {

struct LumenCheck {
  /// Largest difference in colon arclength between the tracks of adjacent slices, beyond
  /// the scope's own length between them (0 when no adjacent pair exceeds it) [m].
  double track_jump_m = 0;
  /// Deepest interaction point beyond the wall it is tracked on: |x - M(track)| minus the
  /// lumen radius there (0 when every point is inside) [m].
  double wall_penetration_m = 0;
  /// Some slice centre (on the scope's axis) lies outside the lumen of its track and
  /// outside it at its nearest point on that colon segment and both its neighbours.
  bool lumen_exit = false;
};

/// Measures the state's contact topology (see above). `arc_scratch` holds the present
/// arclength at each control point (resized to n; reused across calls, so that measuring
/// every step allocates nothing once it has its size).
LumenCheck checkLumen(const WorldModel& model, const WorldState& state, std::vector<double>& arc_scratch);

}  // namespace colosim
