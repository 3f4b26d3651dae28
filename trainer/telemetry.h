// What a simulation reports after each step, for scoring and overlays: plain data.
#pragma once

#include <vector>

#include "core/handle_input.h"
#include "core/spline.h"

namespace colosim {

/// One step's measurements. A simulation that cannot measure something (the colon-only
/// simulation has no scope and no camera) documents the neutral value it reports.
struct Telemetry {
  double time_s = 0.0;            ///< simulated time at the end of the step [s]
  HandleInput input;              ///< the handle input the step used
  double handle_force_N = 0.0;    ///< axial force the hand applies to the scope, + = push [N]
  double handle_torque_Nm = 0.0;  ///< axial torque the hand applies, + = clockwise seen by the operator [N m]
  double wall_force_peak_N = 0.0; ///< largest single scope-wall contact force this step [N]
  Vec3 tip_position_m = Vec3::Zero();  ///< scope tip in the patient frame [m]
  double tip_to_caecum_m = 1e9;   ///< distance from the tip to the caecal pole [m]
  /// How far along the colon the tip is [m]: the rest arclength from the anus of the colon
  /// location nearest the tip (the colon's rest length at the caecal pole; 0 outside).
  double tip_arclength_m = 0.0;
  /// Mesentery stretch, the discomfort source [-]: the largest, over the colon's control
  /// points, of the mesentery lifter force on the point over the weight the point carries
  /// (lifter force per unit length over weight per unit length; mesenteryStretch in
  /// trainer/colon_simulation.h). About 1 where the attachments just carry the hanging
  /// colon (up to ~3 at the flexures, which also carry the free segments); more where the
  /// scope stretches them.
  double mesentery_stretch = 0.0;
  /// Loop measure [turns]: the scope from the anus to the end of the descending colon, projected on
  /// the coronal plane, as fluoroscopy shows it; the signed turning number of the largest
  /// closed loop it makes by crossing itself (crossingLoopTurns below): +-1 for an alpha
  /// loop, 0 when the projection does not cross itself (a straight or merely curved
  /// sigmoid, an N loop). Positive: anticlockwise seen from the front of the patient.
  double loop_turns = 0.0;
  bool tip_against_wall = false;  ///< red-out: the lens touches the mucosa
  bool lumen_visible = true;      ///< the lumen ahead is in the onboard view
  /// Wall patches lit and in the onboard view within 5 cm this step (ids in [0, patch_count)).
  std::vector<int> patches_seen;
  int patch_count = 0;            ///< number of wall patches of the colon (0: not measured)
  /// Quantities the solver limits changed in this step (limitedCount in core/world.h:
  /// contact forces scaled down, segments and control points slowed, failed solves); 0
  /// when the solvers kept up (docs/hardening.md).
  int solver_limited = 0;
  /// The contact topology after the step (core/lumen_check.h): the largest jump in colon
  /// arclength between adjacent slices' tracks beyond the scope length between them [m],
  /// the deepest interaction point beyond the wall it is tracked on [m], and whether some
  /// slice centre lies outside the lumen of its track. 0, 0, false without a scope.
  double track_jump_m = 0.0;
  double wall_penetration_m = 0.0;
  bool lumen_exit = false;
};

/// Net turning of a polyline projected on the plane normal to `normal` [turns]:
/// the sum of the signed angles between successive projected segments, over 2 pi.
/// Positive is anticlockwise seen from the tip of `normal`. A full circle gives +-1, an
/// S shape ~0. Segments shorter than 1e-9 m after projection are skipped.
double netTurns(const std::vector<Vec3>& polyline_m, const Vec3& normal);

/// Loop measure by self-crossing [turns]. The polyline is projected on the plane normal
/// to `normal`; wherever two non-adjacent segments a < b cross, at X, the path
/// X -> P[a+1] -> ... -> P[b] -> X is a closed loop, and its turning number (the sum of
/// the signed turning angles at its corners, X included, over 2 pi) is an integer: +-1
/// for a simple loop, +-2 for a loop wound twice. Returns the turning number of largest
/// magnitude over all crossings (the first found among equals), signed as netTurns
/// (positive anticlockwise seen from the tip of `normal`); 0 without crossing. Segments
/// shorter than 1e-9 m after projection, and parallel segments, never cross.
/// O(n^2) in the number of points (a few dozen here).
double crossingLoopTurns(const std::vector<Vec3>& polyline_m, const Vec3& normal);

}  // namespace colosim
