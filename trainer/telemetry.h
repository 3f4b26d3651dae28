// What a simulation reports after each step, for scoring and overlays: plain data.
#pragma once

#include <string>
#include <vector>

#include "core/colon_model.h"
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
  double wall_force_total_N = 0.0;///< sum of the magnitudes of all scope-wall contact forces this step [N]
  Vec3 tip_position_m = Vec3::Zero();  ///< scope tip in the patient frame [m]
  double tip_to_caecum_m = 1e9;   ///< distance from the tip to the caecal pole [m]
  /// How far along the colon the tip is [m]: the rest arclength from the anus of the colon
  /// location nearest the tip (the colon's rest length at the caecal pole; 0 outside).
  double tip_arclength_m = 0.0;
  /// Mesentery stretch, the discomfort source [-]: the largest, over the colon's control
  /// points, of the mesentery lifter force on the point beyond the one it has in the resting
  /// patient (the colon settled under gravity, scope out: restingColon), over the weight the
  /// point carries (per unit length over weight per unit length; mesenteryStretch in
  /// trainer/colon_simulation.h). 0 at rest; 1 where a lifter carries its colon's weight
  /// again on top of its resting load; more where the scope stretches it.
  double mesentery_stretch = 0.0;
  /// The colon pulled longer than it is at rest, the discomfort source [-]: the largest,
  /// over the anatomy's regions, of present/rest length - 1 (region_length_ratio below),
  /// 0 when no region is longer than at rest. A loop pushed on stretches the colon between
  /// its attachments; what hurts is that stretch of the colon and its attachments
  /// (docs/clinical-mechanics.md, "Discomfort").
  double colon_stretch = 0.0;
  /// Loop measure [turns]: the scope from the anus to the end of the descending colon, projected on
  /// the coronal plane, as fluoroscopy shows it; the signed turning number of the largest
  /// closed loop it makes by crossing itself (crossingLoopTurns below): +-1 for an alpha
  /// loop, 0 when the projection does not cross itself (a straight or merely curved
  /// sigmoid, an N loop). Positive: anticlockwise seen from the front of the patient.
  double loop_turns = 0.0;
  /// Loop measure in 3-D [turns]: the writhe of the same line (the scope from the anus
  /// through the sigmoid and descending colon) closed far away by straight rays, out of the
  /// anus and up from its far end (writheClosedFarAway below). About +-1 for an alpha loop whatever the view; near 0
  /// for a straight or merely bent scope. Its sign is the loop's handedness.
  double loop_writhe = 0.0;
  /// Scope length past the anus [m]: the commanded insertion less the grip's slip (0
  /// without a scope).
  double inserted_m = 0.0;
  /// Present over rest length of each anatomy region of the colon [-] (regionLengthRatios
  /// below), by region index; its names in region_names. Below 1: the region is shortened,
  /// pleated onto the scope. Empty when not measured.
  std::vector<double> region_length_ratio;
  /// Names of region_length_ratio's entries (the colon model's; must outlive the record).
  const std::vector<std::string>* region_names = nullptr;
  bool abdominal_pressure = false;  ///< an assistant is pressing on the abdomen (AssistInput)
  /// The patient's position (its target while the patient is being turned); empty when
  /// the simulation does not say.
  std::string patient_position;
  bool patient_turning = false;     ///< the patient is being turned (gravity is rotating)
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

/// Writhe of the polyline closed by the straight chord from its last point to its first
/// [turns]: the Gauss double integral over the closed polygon, (1 / 4 pi) times the sum of
/// the signed solid angles of every pair of non-adjacent edges, each exact (Klenin &
/// Langowski 2000, method 1a). 0 for a planar curve; about +-1 for a loop whose limbs cross
/// with the sign of that crossing (knot theory's: +1 when the upper limb's direction crossed
/// with the lower limb's points at the viewer, a right-handed crossing); it changes sign
/// under a mirror image and is unchanged by rotation, translation and scale.
/// Null segments are skipped. O(n^2).
double closedWrithe(const std::vector<Vec3>& polyline_m);

/// Writhe of the polyline closed far away [turns]: each end extended by a ray, the start
/// along out_start and the end along out_end, the rays joined far from the curve (closedWrithe
/// of that polygon). A chord between the ends of a loop passes close to its crossing, and the
/// writhe jumps by 2 each time a limb moves through the chord; rays pointing away from the
/// body (out of the anus, up the descending colon) are never crossed by the scope's loop.
double writheClosedFarAway(const std::vector<Vec3>& polyline_m, const Vec3& out_start, const Vec3& out_end);

/// Present over rest length of each region of the colon [-], by region index: the sum of
/// the chord lengths |q_{j+1} - q_j| of the region's spline segments over the sum of their
/// rest chord lengths (ColonModel::rest_length_m). `ratios` is resized to the region count.
void regionLengthRatios(const ColonModel& colon, const Points& q, std::vector<double>& ratios);

/// The colon's stretch [-] from regionLengthRatios' ratios: the largest ratio - 1, at
/// least 0 (Telemetry::colon_stretch).
double colonStretch(const std::vector<double>& region_length_ratios);

}  // namespace colosim
