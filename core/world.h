// The whole physical world of a colonoscopy: colon, colonoscope and their contacts, and the
// step pipeline that advances them together. Contact queries come through the abstract
// ContactQuery (implemented with FCL in collision/), so core stays free of FCL.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/abdominal_pressure.h"
#include "core/colon_model.h"
#include "core/colon_state.h"
#include "core/contact.h"
#include "core/handle_input.h"
#include "core/scope_model.h"
#include "core/scope_state.h"

namespace colosim {

struct WorldModel {
  ColonModel colon;
  ScopeModel scope;
  ContactParams contact;
};

/// The scope enters at the colon's first control point (the anus), along the spline's
/// tangent there; d2 ("up") faces anterior (-y) at zero handle rotation.
WorldModel makeWorldModel(ColonModel colon, const ScopeParams& scope, const ContactParams& contact);

class StepLanes;

struct WorldState {
  ColonState colon;
  ScopeState scope;
  std::vector<WallContact> wall;   ///< wall contacts found at the start of the last step
  std::vector<SelfContact> self;   ///< colon self-contacts found at the start of the last step
  /// Threading contacts found at the start of the last step (core/colon_threading.h).
  std::vector<WallContact> threading;
  /// The threading stops of the last step (core/colon_threading.h: stopThreading), and
  /// scratch: the candidates they were chosen from.
  struct ThreadingStop {
    int scope_segment = 0;
    Vec3 lever_W = Vec3::Zero();   ///< axis point minus the segment's centre at the start [m]
    int point = 0;                 ///< colon control point
    Vec3 normal_W = Vec3::UnitX(); ///< from the control point towards the axis point
    double depth_m = 0;            ///< at the start of the step (negative: short of a contact) [m]
    double allowed_m = 0;          ///< the deepest it may go within the step [m]
    double impulse_Ns = 0;         ///< what stopped it [N s]
  };
  std::vector<ThreadingStop> threading_stops;
  std::vector<WallContact> threading_near;
  /// Per interaction point: its spline location in the last step (core/contact_tracking.h),
  /// segment-major (k * P + i, P = interaction_points_S.size()), then the tip face's points
  /// (K * P + f).
  std::vector<WallTrack> track;
  /// Per slice of interaction points (k * slices_per_segment + slice): the spline location
  /// of its centre on the scope's axis in the last step (the contact topology).
  std::vector<WallTrack> slice_track;
  double max_wall_force_N = 0;     ///< largest interaction-point force in the last step [N]
  ContactLimitReport contact_limit;  ///< what the contact force limit did in the last step
  /// Abdominal pressure (core/abdominal_pressure.h), one entry per pressure of the scenario:
  /// the simulation sets each one's k and c for the next step from its scenario (0 while it
  /// is off) and its anchor when the pressing begins; anchors are state (hashed).
  std::vector<RegionSupport> support;
  /// Scratch: the colon at the start of the step, to step it again with the lens guard's
  /// reaction (stepWorld). Sized by makeWorldState() so that the step allocates nothing.
  struct ColonStart {
    Points q, v;
    double time_s = 0;
    std::vector<double> tension_internal;
  } colon_start;
  /// Scratch: the wall contacts' stiffness per body that limits the coupling predictor
  /// (applyWallContacts). Sized by makeWorldState().
  CouplingStiffness coupling_stiffness;
  /// Where the lens guard's wall is this step: the tip slice's track (-1: no guard).
  int lens_wall_segment = -1;
  double lens_wall_p = 0;
};

/// How many quantities the solver limits changed in the last step (docs/hardening.md):
/// contact forces scaled down or dropped, scope segments and colon control points slowed,
/// failed or non-finite solves, the handle force or torque limited (the grip slipped). 0 in a step the solvers kept up with.
int limitedCount(const WorldState& state);

WorldState makeWorldState(const WorldModel& model);

/// Finds the contacts of the current state.
class ContactQuery {
 public:
  virtual ~ContactQuery() = default;
  /// Fills state.wall with the interaction points outside the lumen and updates state.track.
  virtual void findWallContacts(const WorldModel& model, WorldState& state) = 0;
  /// Fills state.self with the intersecting, non-neighbouring colon sphere pairs.
  virtual void findSelfContacts(const WorldModel& model, WorldState& state) = 0;
};

/// One step of the world, dt_s [s]: contacts (query, then the threading contacts of its
/// tracks), contact forces, abdominal pressure
/// (state.support), the lens guard's wall (ScopeState::lens_wall), colon step, scope step;
/// when the guard engaged (ScopeState::lens_impulse_Ns > 0), the colon is stepped again
/// from its start with the guard's reaction added to its loads. With lanes
/// (core/step_lanes.h), the wall and self queries run at the same time, and so do the
/// colon and scope steps: the same bits as without (the query's two finds must then not
/// share scratch data; both shipped queries keep them apart).
void stepWorld(const WorldModel& model, WorldState& state, const HandleInput& input, ContactQuery& query,
               double dt_s, StepLanes* lanes = nullptr);

/// The interaction point i of scope segment k in the world [m].
inline Vec3 interactionPoint(const ScopeModel& m, const ScopeState& s, int k, int i) {
  return s.p_W[k] + s.R_WS[k] * m.interaction_points_S[i];
}

/// Tip face point f (ScopeModel::tip_face_points_S) in the world [m].
inline Vec3 tipFacePoint(const ScopeModel& m, const ScopeState& s, int f) {
  return s.p_W[0] + s.R_WS[0] * m.tip_face_points_S[f];
}

/// The centre of slice `slice` of scope segment k, on the scope's axis, in the world [m].
inline Vec3 sliceCentre(const ScopeModel& m, const ScopeState& s, int k, int slice) {
  const double z = m.interaction_points_S[static_cast<size_t>(slice) * m.params.points_per_slice].z();
  return s.p_W[k] + s.R_WS[k] * Vec3(0, 0, z);
}

/// Places the scope along the colon's current centreline from the anus to depth
/// insertion_m (clamped to the colon's length), at rest, with the given handle rotation:
/// a start state "inserted to depth L" without simulating the insertion. Tracks are reset.
/// The joints are closed: each segment is a chord of length h of the centreline, from the
/// first segment outside to the tip. The bent scope is not yet held by the wall: relax it
/// before use (trainer/start_state.h).
void threadScopeAlongColon(const WorldModel& model, WorldState& state, double insertion_m,
                           double rotation_rad = 0.0);

/// 64-bit hash of the whole physical state (colon, scope, contact tracks).
uint64_t hashWorldState(const WorldState& state);

}  // namespace colosim
