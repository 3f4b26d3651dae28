// Contact tracking: which part of the colon each interaction point of the scope is in, and
// the wall contacts that follow (paper section 2.5: the nearest spline point M_j(p) of an
// interaction point I is a contact when |I - M_j(p)| exceeds the lumen radius there).
//
// The paper finds M_j(p) by scanning the whole spline (scanWallContacts, kept as the
// reference). Where parts of the colon lie against each other (sigmoid on rectum, a loop,
// the transverse colon on a flexure), the nearest spline point can belong to another part
// than the one the scope is in; taking it lets the scope pass through the wall. The scope
// enters at the anus and runs inside the lumen, so the part each slice is in follows from
// its proximal neighbour's: the contact topology. The rule, per step
// (ContactTracker::trackWallContacts):
// A point inside the lumen where the walk by distance leaves it is inside the colon, however
// near the centreline of a narrower pleat gathered against that wall: it stays there.
// Outside it, locations are compared by clearance: the distance from the centreline less
// the lumen radius there. The wall is the envelope of the lumen's cross-sections, so where
// the lumen tapers (the rectum's 22 mm narrowing to the sigmoid's 17.5 mm within one
// segment) the wall nearest a point lies towards the wider end, not at the nearest
// centreline point.
//  1. Chain: the slice centres on the scope's axis are located from the anus to the tip.
//     The first slice inside is anchored at the anus (the colon's start), every later one at
//     its proximal neighbour's location. From its anchor a slice walks along the spline to
//     the local minimum of the distance and, outside the lumen there, on to that of the
//     clearance (walkToLeastClearance). It also walks from where it
//     was a step ago (state.slice_track) and keeps the one of less clearance: the colon moves
//     less than a few mm in a step, so that walk stays in its lumen too, and it holds a
//     slice whose neighbour's walk stops short in a fold.
//  2. Same part: the search behind ContactQuery (the broadphase, collision/) offers the
//     location of least clearance on the other colon segments near the slice's scope
//     segment (TrackingCandidates, exact: it depends on the present colon alone). One of
//     less clearance takes over only when the colon from the anchor to
//     it stays near the slice (colonStaysNear: every control point between within
//     ContactParams::self_neighbour_radii lumen radii of it): a fold or a pleat of the part
//     the slice is in, where the walk stopped at a shallow minimum. Another part that only
//     lies against it (a sigmoid folded down on the rectum, the other side of a loop) is
//     reached along the colon through places far from the slice, and never takes over.
//     So a slice never changes lumen through the wall, and tracks are continuous along the
//     scope from the anus. A tip turned back along the colon (retroflexion) is followed
//     the same way, slice by slice.
//  3. Points: each interaction point is anchored at its slice centre's location (rules 1-2);
//     the tip face's points at the tip slice's.
//  4. Inside: a slice whose whole ring is provably inside the lumen (centre distance plus
//     scope radius within the smallest lumen radius around its location) has no contact;
//     nor has a point within that radius of the slice centre's spline point. Their tracks
//     take the slice centre's location.
//  5. Outside the patient: points of segments outside the anus lose their tracks.
// docs/hardening.md ("Contact tracking") tells the history of the rule.
#pragma once

#include <vector>

#include "core/spline.h"
#include "core/world.h"

namespace colosim {

/// A spline location and its distance from a query point.
struct SplineLocation {
  int j = -1;        ///< colon segment, -1 when none
  double p = 0;      ///< parameter on it
  double d = 1e300;  ///< distance [m]
};

/// How far x at distance `at.d` from the centreline lies beyond the lumen wall there
/// (negative: inside) [m].
inline double clearance(const ColonModel& colon, const SplineLocation& at) {
  return at.d - colon.radiusAt(at.j, at.p);
}

/// The cubics of every colon segment of the current centreline (resized to n - 1).
void updateSegmentCubics(const Points& q, std::vector<SegmentCubic>& cubics);

/// Replaces `best` by the nearest point of segment j to x when that is strictly nearer.
void considerSegment(const std::vector<SegmentCubic>& cubics, int j, const Vec3& x, SplineLocation& best);

/// Replaces `best` (of clearance `least` [m]) by the point of segment j nearest x when its
/// clearance is strictly less; whether it did.
bool considerSegmentByClearance(const std::vector<SegmentCubic>& cubics, const ColonModel& colon, int j, const Vec3& x,
                                SplineLocation& best, double& least);

/// The local minimum of the distance from x along the spline, walking from segment `start`
/// (-1: none, returned as such): while the minimum sits at a segment end, the next segment
/// is tried.
SplineLocation walkToNearest(const std::vector<SegmentCubic>& cubics, const Vec3& x, int start);

/// For x outside the lumen at the distance's local minimum (walkToNearest from segment
/// `start`; -1: none, returned as such), the local minimum of the clearance along the
/// spline (each segment at its point nearest x): on to the next segment either way while
/// it has less clearance. Where the lumen tapers (the rectum's 22 mm to the sigmoid's
/// 17.5 mm in one segment) the wall nearest x is not at the nearest centreline point but
/// towards the wider end. For x inside the lumen there, that location: x is in the colon,
/// and a walk on to wider places would only drift along the colon.
SplineLocation walkToLeastClearance(const std::vector<SegmentCubic>& cubics, const ColonModel& colon, const Vec3& x,
                                    int start);

/// Rule 2: whether the colon between locations a and b (j >= 0) stays within reach_m of x at
/// every control point between them (`cubics`: the present centreline).
bool colonStaysNear(const std::vector<SegmentCubic>& cubics, const SplineLocation& a, const SplineLocation& b,
                    const Vec3& x, double reach_m);

/// The wall contact of interaction point i of scope segment k at x, located at `at`, when x
/// lies outside the lumen there; appended to `out`.
void recordIfOutside(const WorldModel& model, const std::vector<SegmentCubic>& cubics, int k, int i,
                     const Vec3& x, const SplineLocation& at, std::vector<WallContact>& out);

/// Rule 5: resets the tracks of the interaction points of segments outside the patient.
void resetOutsideTracks(const WorldModel& model, WorldState& state);

/// The paper's method, the reference: every interaction point of the simulated segments
/// takes the place of least clearance on the whole spline (`cubics` of state.colon; each
/// segment at its point nearest the point: the paper's nearest point where the radius is
/// constant), the tip face's points and the slice centres too; fills state.wall,
/// state.track and state.slice_track.
void scanWallContacts(const WorldModel& model, const std::vector<SegmentCubic>& cubics, WorldState& state);

/// What a candidate search (a broadphase) offers the tracking (rule 2).
class TrackingCandidates {
 public:
  virtual ~TrackingCandidates() = default;
  /// The location of least clearance to x (each segment at its point nearest x) on the
  /// colon segments near scope segment k, leaving out local.j - 1 .. local.j + 1; none
  /// (j = -1) when no such segment has less clearance than `local_clearance_m`. Exact: a
  /// segment is skipped only when a lower bound of its clearance rules it out, so the
  /// answer depends on the colon and x alone.
  virtual SplineLocation nearestOther(const std::vector<SegmentCubic>& cubics, const ColonModel& colon,
                                      const Vec3& x, int k, const SplineLocation& local,
                                      double local_clearance_m) = 0;
};

/// The tracked narrowphase (rules 1-5), with its scratch.
class ContactTracker {
 public:
  explicit ContactTracker(const WorldModel& model);
  /// The cubics of state.colon's centreline, for this step's queries.
  void updateCubics(const ColonState& colon);
  const std::vector<SegmentCubic>& cubics() const { return cubics_; }
  /// Fills state.wall with the interaction points outside the lumen and sets state.track
  /// and state.slice_track (updateCubics() first).
  void trackWallContacts(const WorldModel& model, WorldState& state, TrackingCandidates& candidates);
  /// Rules 1-2 for one point x of scope segment k anchored at `anchor` (j >= 0): its
  /// location on the part of the colon the anchor is on.
  SplineLocation nearestOnPart(const WorldModel& model, const Vec3& x, const SplineLocation& anchor, int k,
                               TrackingCandidates& candidates);

 private:
  std::vector<SegmentCubic> cubics_;
  std::vector<SplineLocation> axes_;  // per scope segment and slice: the slice centre's location
};

}  // namespace colosim
