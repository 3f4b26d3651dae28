#include "core/lumen_check.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/spline.h"

namespace colosim {

LumenCheck checkLumen(const WorldModel& m, const WorldState& s, std::vector<double>& arc) {
  LumenCheck out;
  const ColonModel& colon = m.colon;
  const ScopeModel& scope = m.scope;
  // Present arclength at each control point, over the chords [m].
  arc.assign(colon.n, 0.0);
  for (int j = 0; j + 1 < colon.n; ++j) arc[j + 1] = arc[j] + (s.colon.q.col(j + 1) - s.colon.q.col(j)).norm();
  auto arclength = [&](const WallTrack& t) { return arc[t.colon_segment] + t.p * (arc[t.colon_segment + 1] - arc[t.colon_segment]); };

  const int P = static_cast<int>(scope.interaction_points_S.size());
  const int per_slice = scope.params.points_per_slice;
  const int slices = scope.params.slices_per_segment;
  const double slice_length_m = scope.h_m / slices;
  // The centreline point and radius of the last track asked for: the points of a slice
  // inside the lumen share their slice centre's track, so most tracks come in runs.
  WallTrack last{-1, 0.0};
  Vec3 last_point = Vec3::Zero();
  double last_radius = 0;
  auto beyondWall = [&](const Vec3& x, const WallTrack& t) {
    if (t.colon_segment != last.colon_segment || t.p != last.p) {
      last = t;
      last_point = splinePoint(s.colon.q, t.colon_segment, t.p);
      last_radius = colon.radiusAt(t.colon_segment, t.p);
    }
    return (x - last_point).norm() - last_radius;
  };
  // The track is the step's start one: where the scope slides along a taper it can lag
  // the slice by a segment end (the tip 0.1 mm beyond the wall at its track, inside at the
  // nearest point of the next segment, which the next step's tracking finds). A centre is
  // out of the lumen when it is beyond the wall at its nearest point on the tracked
  // segment and on both its neighbours (1.5 cm of colon each way; a scope that tunnelled
  // to another part of the colon is far from all three).
  auto insideNear = [&](const Vec3& x, int j) {
    for (int jj = std::max(0, j - 1); jj <= std::min(colon.n - 2, j + 1); ++jj) {
      const ClosestPoint c = closestPointOnSegment(s.colon.q, jj, x);
      if (c.distance - colon.radiusAt(jj, c.p) <= 0) return true;
    }
    return false;
  };
  bool have_previous = false;
  double previous_arc = 0;
  // Slices from the anus to the tip: segment inside-1 is the deepest-in proximal one.
  for (int k = s.scope.inside - 1; k >= 0; --k) {
    for (int sl = 0; sl < slices; ++sl) {
      const WallTrack& t = s.slice_track[static_cast<size_t>(k) * slices + sl];
      if (t.colon_segment < 0) {
        have_previous = false;
        continue;
      }
      const double a = arclength(t);
      if (have_previous) out.track_jump_m = std::max(out.track_jump_m, std::abs(a - previous_arc) - slice_length_m);
      have_previous = true;
      previous_arc = a;
      const Vec3 centre = sliceCentre(scope, s.scope, k, sl);
      const double centre_beyond_m = beyondWall(centre, t);
      if (!out.lumen_exit && centre_beyond_m > 0 && !insideNear(centre, t.colon_segment)) out.lumen_exit = true;
      // The ring's points lie the scope's radius from the centre: those tracked where the
      // centre is are inside when the centre is inside by the radius and a margin (1 nm,
      // far above rounding), so they cannot raise the deepest penetration (from 0).
      const bool ring_inside = centre_beyond_m + scope.radius_m + 1e-9 <= 0;
      for (int i = sl * per_slice; i < (sl + 1) * per_slice; ++i) {
        const WallTrack& ti = s.track[static_cast<size_t>(k) * P + i];
        if (ti.colon_segment < 0) continue;
        if (ring_inside && ti.colon_segment == t.colon_segment && ti.p == t.p) continue;
        out.wall_penetration_m = std::max(out.wall_penetration_m, beyondWall(interactionPoint(scope, s.scope, k, i), ti));
      }
    }
  }
  if (s.scope.inside > 0)
    for (size_t f = 0; f < scope.tip_face_points_S.size(); ++f) {
      const WallTrack& tf = s.track[static_cast<size_t>(scope.segment_count) * P + f];
      if (tf.colon_segment >= 0)
        out.wall_penetration_m = std::max(out.wall_penetration_m, beyondWall(tipFacePoint(scope, s.scope, static_cast<int>(f)), tf));
    }
  return out;
}

}  // namespace colosim
