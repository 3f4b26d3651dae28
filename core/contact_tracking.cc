#include "core/contact_tracking.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace colosim {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

void updateSegmentCubics(const Points& q, std::vector<SegmentCubic>& cubics) {
  const int n = static_cast<int>(q.cols());
  cubics.resize(n - 1);
  for (int j = 0; j + 1 < n; ++j) cubics[j] = segmentCubic(q, j);
}

void considerSegment(const std::vector<SegmentCubic>& cubics, int j, const Vec3& x, SplineLocation& best) {
  double d;
  const double p = closestParameterOnCubic(cubics[j], x, 0.0, 1.0, &d);
  if (d < best.d) best = {j, p, d};
}

bool considerSegmentByClearance(const std::vector<SegmentCubic>& cubics, const ColonModel& colon, int j, const Vec3& x,
                                SplineLocation& best, double& least) {
  SplineLocation at;
  considerSegment(cubics, j, x, at);
  const double c = clearance(colon, at);
  if (!(c < least)) return false;
  best = at;
  least = c;
  return true;
}

SplineLocation walkToNearest(const std::vector<SegmentCubic>& cubics, const Vec3& x, int start) {
  SplineLocation local;
  if (start < 0) return local;
  const int nseg = static_cast<int>(cubics.size());
  int j = std::min(start, nseg - 1);
  considerSegment(cubics, j, x, local);
  int lo = j, hi = j;
  for (int it = 0; it < nseg; ++it) {
    if (local.p <= 0.0 && lo > 0) {
      const SplineLocation before = local;
      considerSegment(cubics, --lo, x, local);
      if (local.j == before.j) break;
    } else if (local.p >= 1.0 && hi < nseg - 1) {
      const SplineLocation before = local;
      considerSegment(cubics, ++hi, x, local);
      if (local.j == before.j) break;
    } else {
      break;
    }
  }
  return local;
}

SplineLocation walkToLeastClearance(const std::vector<SegmentCubic>& cubics, const ColonModel& colon, const Vec3& x,
                                    int start) {
  SplineLocation best = walkToNearest(cubics, x, start);
  if (best.j < 0) return best;
  double least = clearance(colon, best);
  if (!(least > 0)) return best;  // inside the lumen there: that is where it is
  const int nseg = static_cast<int>(cubics.size());
  for (int step : {-1, 1}) {
    bool moved = false;
    for (int j = best.j + step; j >= 0 && j < nseg; j += step) {
      if (!considerSegmentByClearance(cubics, colon, j, x, best, least)) break;
      moved = true;
    }
    if (moved) break;
  }
  return best;
}

bool colonStaysNear(const std::vector<SegmentCubic>& cubics, const SplineLocation& a, const SplineLocation& b,
                    const Vec3& x, double reach_m) {
  const int lo = std::min(a.j, b.j), hi = std::max(a.j, b.j);
  const double reach2 = reach_m * reach_m;
  for (int j = lo + 1; j <= hi; ++j)  // control point j starts segment j
    if ((cubics[j].c0 - x).squaredNorm() > reach2) return false;
  return true;
}

void recordIfOutside(const WorldModel& m, const std::vector<SegmentCubic>& cubics, int k, int i, const Vec3& x,
                     const SplineLocation& at, std::vector<WallContact>& out) {
  const double radius = m.colon.radiusAt(at.j, at.p);
  if (!(at.d > radius)) return;
  WallContact c;
  c.scope_segment = k;
  c.point = i;
  c.p_W_point = x;
  c.colon_segment = at.j;
  c.p = at.p;
  c.p_W_centre = cubics[at.j].at(at.p);
  c.normal_W = (x - c.p_W_centre) / at.d;
  c.depth_m = at.d - radius;
  out.push_back(c);
}

void resetOutsideTracks(const WorldModel& m, WorldState& s) {
  const size_t P = m.scope.interaction_points_S.size();
  const size_t ring_points = static_cast<size_t>(m.scope.segment_count) * P;
  for (size_t t = static_cast<size_t>(s.scope.inside) * P; t < ring_points; ++t) s.track[t] = WallTrack();
  if (s.scope.inside == 0)
    for (size_t t = ring_points; t < s.track.size(); ++t) s.track[t] = WallTrack();
  const size_t slices = m.scope.params.slices_per_segment;
  for (size_t t = static_cast<size_t>(s.scope.inside) * slices; t < s.slice_track.size(); ++t) s.slice_track[t] = WallTrack();
}

void scanWallContacts(const WorldModel& m, const std::vector<SegmentCubic>& cubics, WorldState& s) {
  s.wall.clear();
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  const int slices = m.scope.params.slices_per_segment;
  auto nearest = [&](const Vec3& x) {  // the least clearance (each segment at its point nearest x)
    SplineLocation best;
    double least = kInf;
    for (int j = 0; j + 1 < m.colon.n; ++j) considerSegmentByClearance(cubics, m.colon, j, x, best, least);
    return best;
  };
  for (int k = 0; k < s.scope.inside; ++k) {
    for (int sl = 0; sl < slices; ++sl) {
      const SplineLocation at = nearest(sliceCentre(m.scope, s.scope, k, sl));
      s.slice_track[k * slices + sl] = {at.j, at.p};
    }
    for (int i = 0; i < P; ++i) {
      const Vec3 x = interactionPoint(m.scope, s.scope, k, i);
      const SplineLocation best = nearest(x);
      s.track[k * P + i] = {best.j, best.p};
      recordIfOutside(m, cubics, k, i, x, best, s.wall);
    }
  }
  if (s.scope.inside > 0) {
    const int F = static_cast<int>(m.scope.tip_face_points_S.size());
    for (int f = 0; f < F; ++f) {
      const Vec3 x = tipFacePoint(m.scope, s.scope, f);
      const SplineLocation best = nearest(x);
      s.track[m.scope.segment_count * P + f] = {best.j, best.p};
      recordIfOutside(m, cubics, 0, P + f, x, best, s.wall);
    }
  }
  resetOutsideTracks(m, s);
}

ContactTracker::ContactTracker(const WorldModel& m) { cubics_.reserve(m.colon.n); }

void ContactTracker::updateCubics(const ColonState& colon) { updateSegmentCubics(colon.q, cubics_); }

SplineLocation ContactTracker::nearestOnPart(const WorldModel& m, const Vec3& x, const SplineLocation& anchor, int k,
                                             TrackingCandidates& candidates) {
  // 1. Walk along the spline from the anchor to the local minimum of the clearance.
  const SplineLocation local = walkToLeastClearance(cubics_, m.colon, x, anchor.j);
  // 2. A location of less clearance from the candidate search, when the colon from the
  //    anchor to it stays near x (a fold or pleat of the same part). A point inside the
  //    lumen where the walk leaves it is inside the colon, however near the centreline of a
  //    narrower pleat gathered against that wall may be.
  const double local_clearance = clearance(m.colon, local);
  if (!(local_clearance > 0)) return local;
  const SplineLocation other = candidates.nearestOther(cubics_, m.colon, x, k, local, local_clearance);
  if (other.j < 0 || !(clearance(m.colon, other) < local_clearance)) return local;
  const double reach_m = m.contact.self_neighbour_radii * m.colon.radiusAt(anchor.j, anchor.p);
  return colonStaysNear(cubics_, anchor, other, x, reach_m) ? other : local;
}

void ContactTracker::trackWallContacts(const WorldModel& m, WorldState& s, TrackingCandidates& candidates) {
  const ColonModel& colon = m.colon;
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  const int per_slice = m.scope.params.points_per_slice;
  const int slices = m.scope.params.slices_per_segment;
  // 1-2. The chain of slice centres, from the anus (colon segment 0) to the tip: each walks
  //      from its proximal neighbour's location.
  axes_.assign(static_cast<size_t>(s.scope.inside) * slices, SplineLocation());
  SplineLocation anchor{0, 0.0, 0.0};  // the anus
  for (int k = s.scope.inside - 1; k >= 0; --k) {
    for (int sl = 0; sl < slices; ++sl) {
      const Vec3 centre = sliceCentre(m.scope, s.scope, k, sl);
      SplineLocation axis = nearestOnPart(m, centre, anchor, k, candidates);
      // ... or, when nearer, where the slice itself was a step ago, walked from there.
      // (A walk from the segment the axis already lies inside of would only find the axis
      // again: its first closest point is the axis's own, strictly inside the segment.)
      const int before = s.slice_track[k * slices + sl].colon_segment;
      if (before >= 0 && !(before == axis.j && axis.p > 0.0 && axis.p < 1.0)) {
        const SplineLocation own = walkToLeastClearance(cubics_, colon, centre, before);
        if (clearance(colon, own) < clearance(colon, axis)) axis = own;
      }
      axes_[k * slices + sl] = axis;
      s.slice_track[k * slices + sl] = {axis.j, axis.p};
      anchor = axis;
    }
  }
  // 3. Each slice's points, from the slice centre's location.
  s.wall.clear();
  for (int k = 0; k < s.scope.inside; ++k) {
    for (int sl = 0; sl < slices; ++sl) {
      const SplineLocation& axis = axes_[k * slices + sl];
      const int first = sl * per_slice;
      // 4. A slice whose whole ring is provably inside the lumen (centre distance + scope
      //    radius <= the smallest nearby radius): no point of it can touch the wall.
      double r_min = kInf;  // the smallest lumen radius around the slice's location [m]
      for (int i = std::max(0, axis.j - 1); i <= std::min(colon.n - 1, axis.j + 2); ++i)
        r_min = std::min(r_min, colon.radius_m(i));
      if (axis.d + m.scope.radius_m <= r_min) {
        for (int i = first; i < first + per_slice; ++i) s.track[k * P + i] = {axis.j, axis.p};
        continue;
      }
      const Vec3 axis_point = cubics_[axis.j].at(axis.p);
      for (int i = first; i < first + per_slice; ++i) {
        const Vec3 x = interactionPoint(m.scope, s.scope, k, i);
        WallTrack& track = s.track[k * P + i];
        // The same test per point: the spline point nearest the slice's centre is at most
        // |x - axis_point| from x, so x is inside the lumen when that is within r_min (the
        // points on the side of the scope away from the wall).
        if ((x - axis_point).squaredNorm() <= r_min * r_min) {
          track = {axis.j, axis.p};
          continue;
        }
        const SplineLocation best = nearestOnPart(m, x, axis, k, candidates);
        track = {best.j, best.p};
        recordIfOutside(m, cubics_, k, i, x, best, s.wall);
      }
    }
  }
  // 3. The tip face's points, from the tip slice's location.
  if (s.scope.inside > 0) {
    const SplineLocation& tip = axes_[slices - 1];
    const int F = static_cast<int>(m.scope.tip_face_points_S.size());
    for (int f = 0; f < F; ++f) {
      const Vec3 x = tipFacePoint(m.scope, s.scope, f);
      const SplineLocation best = nearestOnPart(m, x, tip, 0, candidates);
      s.track[m.scope.segment_count * P + f] = {best.j, best.p};
      recordIfOutside(m, cubics_, 0, P + f, x, best, s.wall);
    }
  }
  // 5. Points outside the patient.
  resetOutsideTracks(m, s);
}

}  // namespace colosim
