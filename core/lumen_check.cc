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
  const int slices = P / per_slice;
  const double slice_length_m = scope.h_m / slices;
  bool have_previous = false;
  double previous_arc = 0;
  // Slices from the anus to the tip: segment inside-1 is the deepest-in proximal one.
  for (int k = s.scope.inside - 1; k >= 0; --k) {
    for (int sl = 0; sl < slices; ++sl) {
      const int first = sl * per_slice;
      const WallTrack& t = s.track[static_cast<size_t>(k) * P + first];
      if (t.colon_segment < 0) {
        have_previous = false;
        continue;
      }
      const double a = arclength(t);
      if (have_previous) out.track_jump_m = std::max(out.track_jump_m, std::abs(a - previous_arc) - slice_length_m);
      have_previous = true;
      previous_arc = a;
      const Vec3 centre = s.scope.p_W[k] + s.scope.R_WS[k] * Vec3(0, 0, scope.interaction_points_S[first].z());
      if ((centre - splinePoint(s.colon.q, t.colon_segment, t.p)).norm() > colon.radiusAt(t.colon_segment, t.p))
        out.lumen_exit = true;
      for (int i = first; i < first + per_slice; ++i) {
        const WallTrack& ti = s.track[static_cast<size_t>(k) * P + i];
        if (ti.colon_segment < 0) continue;
        const double beyond = (interactionPoint(scope, s.scope, k, i) - splinePoint(s.colon.q, ti.colon_segment, ti.p)).norm() -
                              colon.radiusAt(ti.colon_segment, ti.p);
        out.wall_penetration_m = std::max(out.wall_penetration_m, beyond);
      }
    }
  }
  return out;
}

}  // namespace colosim
