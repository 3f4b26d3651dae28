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

SplineLocation keepTrackedPart(const WorldModel& m, const SplineLocation& local, const SplineLocation& other) {
  const ColonModel& colon = m.colon;
  const double ds = std::abs(colon.arclengthAt(other.j, other.p) - colon.arclengthAt(local.j, local.p));
  const bool far_part = ds > m.contact.self_neighbour_radii * colon.radiusAt(local.j, local.p);
  const double reach = colon.radiusAt(local.j, local.p) + m.contact.query_margin_m;
  return (far_part && local.d <= reach) ? local : other;
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
  for (size_t t = static_cast<size_t>(s.scope.inside) * P; t < s.track.size(); ++t) s.track[t] = WallTrack();
}

void scanWallContacts(const WorldModel& m, const std::vector<SegmentCubic>& cubics, WorldState& s) {
  s.wall.clear();
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  for (int k = 0; k < s.scope.inside; ++k) {
    for (int i = 0; i < P; ++i) {
      const Vec3 x = interactionPoint(m.scope, s.scope, k, i);
      SplineLocation best;
      for (int j = 0; j + 1 < m.colon.n; ++j) considerSegment(cubics, j, x, best);
      s.track[k * P + i] = {best.j, best.p};
      recordIfOutside(m, cubics, k, i, x, best, s.wall);
    }
  }
  resetOutsideTracks(m, s);
}

ContactTracker::ContactTracker(const WorldModel& m) { cubics_.reserve(m.colon.n); }

void ContactTracker::updateCubics(const ColonState& colon) { updateSegmentCubics(colon.q, cubics_); }

SplineLocation ContactTracker::nearestTracked(const WorldModel& m, const Vec3& x, int start, int k,
                                              TrackingCandidates& candidates) {
  // 1. Walk along the spline from the tracked location to the local minimum of the distance.
  const SplineLocation local = walkToNearest(cubics_, x, start);
  // 2. Other parts of the colon near x, from the candidate search.
  const SplineLocation other = candidates.nearestOther(cubics_, x, k, local);
  if (local.j < 0) {
    if (other.j >= 0) return other;
    SplineLocation all;  // nothing tracked and nothing near: the paper's scan
    for (int j = 0; j + 1 < m.colon.n; ++j) considerSegment(cubics_, j, x, all);
    return all;
  }
  if (other.j < 0 || other.d >= local.d) return local;
  // 3. Another part is nearer: it takes over unless the tracked part is kept.
  return keepTrackedPart(m, local, other);
}

void ContactTracker::trackWallContacts(const WorldModel& m, WorldState& s, TrackingCandidates& candidates) {
  const ColonModel& colon = m.colon;
  // 4. The slices' centres on the scope axis, from the anus to the tip; a slice located on
  //    a far part from its proximal neighbour's location takes the neighbour's lumen when
  //    its centre lies deeper in it (and within reach of it).
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  const int per_slice = m.scope.params.points_per_slice;
  const int slices = P / per_slice;
  axes_.assign(static_cast<size_t>(s.scope.inside) * slices, SplineLocation());
  moved_.assign(axes_.size(), 0);
  for (int k = s.scope.inside - 1; k >= 0; --k) {
    for (int sl = 0; sl < slices; ++sl) {
      const int first = sl * per_slice;
      const Vec3 centre = s.scope.p_W[k] + s.scope.R_WS[k] * Vec3(0, 0, m.scope.interaction_points_S[first].z());
      SplineLocation axis = nearestTracked(m, centre, s.track[k * P + first].colon_segment, k, candidates);
      const SplineLocation before = k + 1 < s.scope.inside ? axes_[(k + 1) * slices + sl] : SplineLocation();
      if (axis.j >= 0 && before.j >= 0) {
        const double ds = std::abs(colon.arclengthAt(axis.j, axis.p) - colon.arclengthAt(before.j, before.p));
        if (ds > m.contact.self_neighbour_radii * colon.radiusAt(before.j, before.p)) {
          const SplineLocation path = walkToNearest(cubics_, centre, before.j);
          const double path_depth = path.d - colon.radiusAt(path.j, path.p);
          if (path_depth <= m.contact.query_margin_m && path_depth < axis.d - colon.radiusAt(axis.j, axis.p)) {
            axis = path;
            moved_[k * slices + sl] = 1;
          }
        }
      }
      axes_[k * slices + sl] = axis;
    }
  }
  // Then each slice's points, from the tip.
  s.wall.clear();
  for (int k = 0; k < s.scope.inside; ++k) {
    for (int first = 0; first < P; first += per_slice) {
      const SplineLocation& axis = axes_[k * slices + first / per_slice];
      const bool moved = moved_[k * slices + first / per_slice];
      // 5. A slice whose whole ring is provably inside the lumen (centre distance + scope
      //    radius <= the smallest nearby radius): no point of it can touch the wall.
      double r_min = -kInf;  // the smallest lumen radius around the slice's location [m]
      Vec3 axis_point = Vec3::Zero();
      if (axis.j >= 0) {
        r_min = kInf;
        for (int i = std::max(0, axis.j - 1); i <= std::min(colon.n - 1, axis.j + 2); ++i)
          r_min = std::min(r_min, colon.radius_m(i));
        if (axis.d + m.scope.radius_m <= r_min) {
          for (int i = first; i < first + per_slice; ++i) s.track[k * P + i] = {axis.j, axis.p};
          continue;
        }
        axis_point = cubics_[axis.j].at(axis.p);
      }
      for (int i = first; i < first + per_slice; ++i) {
        const Vec3 x = interactionPoint(m.scope, s.scope, k, i);
        WallTrack& track = s.track[k * P + i];
        // The same test per point: the spline point nearest the slice's centre is at most
        // |x - axis_point| from x, so x is inside the lumen when that is within r_min (the
        // points on the side of the scope away from the wall).
        if ((x - axis_point).squaredNorm() <= r_min * r_min && r_min > 0) {
          track = {axis.j, axis.p};
          continue;
        }
        // Rules 1-3 from the point's track, or from the slice's location when it has none
        // or rule 4 moved the slice.
        const int start = (track.colon_segment >= 0 && !moved) ? track.colon_segment : axis.j;
        const SplineLocation best = nearestTracked(m, x, start, k, candidates);
        track = {best.j, best.p};
        recordIfOutside(m, cubics_, k, i, x, best, s.wall);
      }
    }
  }
  // 6. Points outside the patient.
  resetOutsideTracks(m, s);
}

}  // namespace colosim
