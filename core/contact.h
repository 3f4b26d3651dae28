// Contacts (paper section 2.5): the colonoscope against the colon wall through
// interaction points, and the colon against itself through spheres along the spline.
// The geometric queries that find them live in collision/ (FCL); the forces live here.
#pragma once

#include <algorithm>
#include <vector>

#include "core/colon_model.h"
#include "core/colon_state.h"
#include "core/scope_model.h"
#include "core/scope_state.h"

namespace colosim {

struct ContactParams {
  /// k_wall per interaction point of a slice wall_reference_slice_m long (eq. 7) [N/m].
  double wall_stiffness_N_per_m = 1000;
  /// f_wall per interaction point of a slice wall_reference_slice_m long (eq. 7) [N s/m].
  double wall_damping_Ns_per_m = 1.0;
  /// The slice length the wall's per-point values (stiffness, damping, max_point_force_N)
  /// are given for [m]. A slice of another length (ScopeParams::segment_length_m /
  /// slices_per_segment) scales them in proportion, so that the wall's stiffness per metre
  /// of scope does not change with the resolution. The tip face's points are not on a
  /// slice and keep the given values. 0: per point whatever the slice (the paper's eq. 7).
  double wall_reference_slice_m = 0.015;
  /// The interaction points round a slice the wall's per-point values are given for: a
  /// slice with another count (ScopeParams::points_per_slice) scales them, and the point
  /// force limit, by this count over its own, so that the wall is as stiff per area of
  /// scope whatever the sampling round it. The tip face's points keep them as given. 0: per
  /// point whatever the count (the paper's eq. 7).
  int wall_reference_points_per_slice = 6;
  /// The wall bottoms out: a distended colon's wall is under 3 mm thick, and a point
  /// pressed deeper than wall_thickness_m presses on what lies behind the wall, not on
  /// mucosa. Beyond it the point's normal force gains wall_backing_stiffness_N_per_m per
  /// metre of the extra depth (per interaction point of a reference slice, scaled like
  /// k_wall). 0: the paper's linear wall at any depth.
  double wall_thickness_m = 0.003;
  double wall_backing_stiffness_N_per_m = 30000;  ///< [N/m]
  /// Threading contacts (core/colon_threading.h): the stiffness holding a colon control
  /// point around the scope where the scope's surface lies beyond the wall's thickness
  /// there, per control point [N/m]. 0: none (the paper's model: the wall is sampled at the
  /// scope's interaction points only).
  double threading_stiffness_N_per_m = 0;
  /// The threading stop (core/colon_threading.h, stopThreading) holds a control point
  /// where its threading spring asks this force [N]: 10 N is 0.33 mm beyond the wall's
  /// thickness at 30,000 N/m, well inside the point force limit (half of it when it was
  /// 20 N, session 28, and kept when the limit was raised, session 29).
  double threading_stop_force_N = 10.0;
  double friction_coefficient = 0.1;      ///< Coulomb mu between scope and mucosa [-] (0: the paper's model)
  double friction_velocity_m_per_s = 0.002; ///< regularisation: full friction above ~this sliding speed [m/s]
  double self_stiffness_N_per_m = 300;    ///< colon self-contact stiffness per sphere pair [N/m]
  double self_damping_Ns_per_m = 1.0;     ///< colon self-contact damping per sphere pair [N s/m]
  /// Spheres closer than this many radii in rest arclength are neighbours and never repel
  /// (pi: a tube folded back on itself with a bend radius equal to its own radius).
  double self_neighbour_radii = 3.14159265358979323846;
  double query_margin_m = 0.01;           ///< how far outside the lumen a point is still found by the broadphase [m]
  /// Solver limit (docs/hardening.md): the largest force one interaction point (or one
  /// threading contact) puts on the wall [N]. 60 N is what the contact laws give 5 mm
  /// deep, the deepest point the lumen tests accept: the wall and its backing 65 N
  /// (1000 N/m x 5 mm + 30,000 N/m x 2 mm), a threading contact 60 N (30,000 N/m x 2 mm).
  /// A point asking more is beyond what the law stands for. A larger force is scaled down
  /// to it, with its stiffness and damping, and counted. (20 N until session 29: where the
  /// body holds the colon firmly, the handle's push wedged points past it into the wall.)
  double max_point_force_N = 60.0;
  /// The lens guard (core/scope_step.h): the lens is stopped this far inside the wall of
  /// the tip slice's track, a margin for what one step's linearisation and the wall's own
  /// motion within the step leave over [m]. Negative: no guard (the penalty wall alone, as
  /// in the paper).
  double lens_margin_m = 0.0005;
  /// How the colon's and the scope's implicit solves share a contact (core/world.h
  /// stepWorld). Each body is solved with the other held over the step, its own motion in the
  /// contact's stiffness. false (the default, as in every step before session 40): the other
  /// body's part of the force stays at its start value, so each feels the other's move a step
  /// late. true: each wall contact carries the other body's move at its start velocity,
  /// limited where both bodies are light against their contacts (applyWallContacts), which
  /// brings a quick push's handle force at 1 ms to a median 0.2 N of a 0.25 ms step (1.3 N
  /// lagging); the threading contacts keep the lag (docs/numerics.md, "The contacts' coupling").
  bool coupling_predictor = false;
  /// Corrections after the first solve (0: none): both bodies solved again from the start
  /// state, each contact carrying the other body's actual move and velocity change of the
  /// previous sweep. Repeated, they converge to the two bodies' implicit step solved
  /// together: the reference the predictor is checked against. Each costs a pair of solves
  /// and copies of both states (they allocate), and it runs on one lane.
  int coupling_sweeps = 0;
};

/// Scratch of the coupling predictor's limit (applyWallContacts): the wall contacts' normal
/// stiffness summed per scope segment (K) and per colon control point (n, through the
/// blending weights' magnitudes) [N/m]. applyWallContacts sizes them; sized already (as
/// makeWorldState does), the step allocates nothing.
struct CouplingStiffness {
  Eigen::VectorXd scope_segment_N_per_m;
  Eigen::VectorXd colon_point_N_per_m;
};

/// The end of a previous sweep of one step (ContactParams::coupling_sweeps).
struct CouplingSweep {
  const ScopeState* scope = nullptr;
  const ColonState* colon = nullptr;
};

/// What the contact force limit did in one call of applyWallContacts.
struct ContactLimitReport {
  int limited = 0;          ///< contacts whose force was scaled down to max_point_force_N
  int non_finite = 0;       ///< contacts dropped because their force was not finite
  double asked_N = 0;       ///< the largest force asked for, before limiting [N]
  /// The limited contact that asked the most (when limited > 0), to say in the solver-limit
  /// event what was limited: its kind, where on the colon, how deep and how fast it closed.
  struct Worst {
    enum class Kind { kSlicePoint, kTipFace, kThreading } kind = Kind::kSlicePoint;
    double asked_N = 0;          ///< its force before limiting [N]
    int colon_segment = -1;      ///< spline segment (a threading contact: its control point)
    double p = 0;                ///< spline parameter
    double depth_m = 0;          ///< its depth [m]
    double closing_m_per_s = 0;  ///< the point's speed into the wall, relative to it [m/s]
  } worst;
  /// Counts another report's contacts into this one (the threading contacts' into the wall's).
  void merge(const ContactLimitReport& other) {
    limited += other.limited;
    non_finite += other.non_finite;
    asked_N = std::max(asked_N, other.asked_N);
    if (other.limited > 0 && other.worst.asked_N > worst.asked_N) worst = other.worst;
  }
};

/// An interaction point of the scope outside the lumen (a query result).
struct WallContact {
  int scope_segment = 0;
  int point = 0;                      ///< index into ScopeModel::interaction_points_S, then tip_face_points_S (P + f)
  Vec3 p_W_point = Vec3::Zero();      ///< interaction point I [m]
  int colon_segment = 0;              ///< nearest spline point M_j(p): segment j ...
  double p = 0;                       ///< ... and parameter p
  Vec3 p_W_centre = Vec3::Zero();     ///< M_j(p) [m]
  Vec3 normal_W = Vec3::Zero();       ///< unit, from M_j(p) towards I (out of the lumen)
  double depth_m = 0;                 ///< |I - M_j(p)| - radius(p) > 0 [m]
  /// Scales the contact's stiffness and damping (1; less for a threading contact handed
  /// over at the end of the scope's chain of slices, core/colon_threading.h).
  double weight = 1.0;
  double force_N = 0;                 ///< magnitude of the contact force (filled by the force stage) [N]
  double normal_force_N = 0;          ///< its normal part, eq. 7 (filled by the force stage) [N]
};

/// Two colon spheres (at control points a < b, not neighbours) that intersect.
struct SelfContact {
  int a = 0, b = 0;
  Vec3 normal_W = Vec3::Zero();  ///< unit, from a towards b
  double depth_m = 0;            ///< r_a + r_b - |q_b - q_a| > 0 [m]
};

/// Where an interaction point last found the wall: its tracked spline location.
struct WallTrack {
  int colon_segment = -1;  ///< -1: not tracked yet
  double p = 0;
};

/// Computes the viscoelastic normal force of eq. 7 with regularised Coulomb friction for
/// every wall contact, and appends the loads on the scope (at the interaction point) and
/// on the colon (at M_j(p), opposite) with their stiffness and damping. Returns the
/// largest contact force magnitude [N] and fills WallContact::force_N. A force above
/// params.max_point_force_N is scaled down to it (force, stiffness and damping alike); a
/// non-finite one is dropped; both are counted in `report` when given.
/// Each body's load holds its own motion in the contact's stiffness K. The other body's part
/// (ContactParams::coupling_predictor, coupling_sweeps) is, with `previous` given, its actual
/// move and velocity change from the start state to the previous sweep's end (K dx and the
/// normal damping times dv); else, with `step_s` > 0, its move at its start velocity over
/// step_s (K v step_s); else nothing. Either way the normal force on either side is kept
/// from going below zero.
/// With `limit` given (and step_s > 0), the predicted part is limited where both bodies are
/// light against their contacts: with a = K_sum step_s^2 / m on each side (K_sum the summed
/// normal stiffness on the scope segment, on the contact's nearest control point; m the
/// segment's effective mass at the point as a free rigid body, and 0.30 of the point's
/// mass-matrix row sum, the matrix's lightest mode), it is scaled by min(1, 1 / (a_scope
/// a_colon)). Each body still solves against the other's predicted move, and the two lanes stay
/// independent; unlimited, the prediction is an explicit coupling that grows without bound
/// when a_scope a_colon exceeds about 4 (docs/numerics.md, "The contacts' coupling").
double applyWallContacts(const ContactParams& params, const ColonModel& colon, const ColonState& colon_state,
                         const ScopeModel& scope, const ScopeState& scope_state,
                         std::vector<WallContact>& contacts, std::vector<SplineLoad>& colon_loads,
                         std::vector<ScopeLoad>& scope_loads, ContactLimitReport* report = nullptr,
                         double step_s = 0.0, const CouplingSweep* previous = nullptr,
                         CouplingStiffness* limit = nullptr);

/// Appends the loads of the colon self-contacts (equal and opposite at the two control points).
void applySelfContacts(const ContactParams& params, const ColonModel& colon, const ColonState& colon_state,
                       const std::vector<SelfContact>& contacts, std::vector<SplineLoad>& colon_loads);

/// True when control points a and b are neighbours along the colon (no self-contact force).
bool selfNeighbours(const ContactParams& params, const ColonModel& colon, int a, int b);

/// The spline location (segment, p) of control point i, for loads applied there.
inline void controlPointLocation(const ColonModel& colon, int i, int* segment, double* p) {
  *segment = (i < colon.n - 1) ? i : colon.n - 2;
  *p = (i < colon.n - 1) ? 0.0 : 1.0;
}

}  // namespace colosim
