// Contact tracking: which part of the colon each interaction point of the scope is in, and
// the wall contacts that follow (paper section 2.5: the nearest spline point M_j(p) of an
// interaction point I is a contact when |I - M_j(p)| exceeds the lumen radius there).
//
// The paper finds M_j(p) by scanning the whole spline (scanWallContacts, kept as the
// reference). Near a loop of the colon that nearest point can jump to another part lying
// against the one the scope is in; tracking keeps each point on its part. The rule, per
// step (ContactTracker::trackWallContacts):
//  1. Walk: from a point's tracked location (its WallTrack), walk along the spline to the
//     local minimum of the distance (walkToNearest).
//  2. Candidates: the search behind ContactQuery (the broadphase, collision/) offers the
//     nearest location on the other colon segments near the point's scope segment
//     (TrackingCandidates).
//  3. Far part: a nearer candidate takes over, unless it is a far part of the colon (more
//     than ContactParams::self_neighbour_radii lumen radii away in arclength: the other
//     side of a loop) while the point is still within reach of the tracked lumen (its
//     radius plus ContactParams::query_margin_m). Nothing tracked and no candidate: the
//     paper's scan.
//  4. Slices along the scope: the centres of the interaction point slices are located
//     first (rules 1-3), from the anus to the tip. The scope runs inside the colon from
//     the anus, so a slice lies next to the same slice of its proximal neighbour along the
//     colon too: a slice located on a far part from the neighbour's location, whose centre
//     lies deeper in the lumen next to the neighbour's location (walked to from there, and
//     within the margin of it), takes that location, and its points walk from it.
//  5. Inside: a slice whose whole ring is provably inside the lumen (centre distance plus
//     scope radius within the smallest lumen radius around its location) has no contact;
//     nor has a point within that radius of the slice centre's spline point. Their tracks
//     take the slice centre's location.
//  6. Outside the patient: points of segments outside the anus lose their tracks.
// docs/hardening.md ("Contact tracking") tells why rules 3 and 4 are as they are.
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

/// The cubics of every colon segment of the current centreline (resized to n - 1).
void updateSegmentCubics(const Points& q, std::vector<SegmentCubic>& cubics);

/// Replaces `best` by the nearest point of segment j to x when that is strictly nearer.
void considerSegment(const std::vector<SegmentCubic>& cubics, int j, const Vec3& x, SplineLocation& best);

/// The local minimum of the distance from x along the spline, walking from segment `start`
/// (-1: none, returned as such): while the minimum sits at a segment end, the next segment
/// is tried.
SplineLocation walkToNearest(const std::vector<SegmentCubic>& cubics, const Vec3& x, int start);

/// Rule 3: the tracked location `local` (j >= 0) or a nearer `other` one (j >= 0, d < local.d)?
SplineLocation keepTrackedPart(const WorldModel& model, const SplineLocation& local, const SplineLocation& other);

/// The wall contact of interaction point i of scope segment k at x, located at `at`, when x
/// lies outside the lumen there; appended to `out`.
void recordIfOutside(const WorldModel& model, const std::vector<SegmentCubic>& cubics, int k, int i,
                     const Vec3& x, const SplineLocation& at, std::vector<WallContact>& out);

/// Rule 6: resets the tracks of the interaction points of segments outside the patient.
void resetOutsideTracks(const WorldModel& model, WorldState& state);

/// The paper's method, the reference: every interaction point of the simulated segments
/// takes the nearest point of the whole spline (`cubics` of state.colon); fills state.wall
/// and state.track.
void scanWallContacts(const WorldModel& model, const std::vector<SegmentCubic>& cubics, WorldState& state);

/// What a candidate search (a broadphase) offers the tracking (rule 2).
class TrackingCandidates {
 public:
  virtual ~TrackingCandidates() = default;
  /// The nearest location to x on the colon segments near scope segment k, leaving out
  /// local.j - 1 .. local.j + 1 when local.j >= 0 and any segment that cannot be nearer
  /// than local.d; none (j = -1) when no such segment is nearer.
  virtual SplineLocation nearestOther(const std::vector<SegmentCubic>& cubics, const Vec3& x, int k,
                                      const SplineLocation& local) = 0;
};

/// The tracked narrowphase (rules 1-6), with its scratch.
class ContactTracker {
 public:
  explicit ContactTracker(const WorldModel& model);
  /// The cubics of state.colon's centreline, for this step's queries.
  void updateCubics(const ColonState& colon);
  const std::vector<SegmentCubic>& cubics() const { return cubics_; }
  /// Fills state.wall with the interaction points outside the lumen and updates
  /// state.track (updateCubics() first).
  void trackWallContacts(const WorldModel& model, WorldState& state, TrackingCandidates& candidates);
  /// Rules 1-3 for one point x of scope segment k, walking from colon segment `start` (-1: none).
  SplineLocation nearestTracked(const WorldModel& model, const Vec3& x, int start, int k,
                                TrackingCandidates& candidates);

 private:
  std::vector<SegmentCubic> cubics_;
  std::vector<SplineLocation> axes_;  // per scope segment and slice: the slice centre's location
  std::vector<char> moved_;           // ... and whether rule 4 took it back to the scope's path
};

}  // namespace colosim
