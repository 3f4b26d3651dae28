// The colonoscope: a chain of short rigid segments joined by elastic joints that resist
// bending (EI) and torsion (GJ) -- the paper's polyarticulated structure, generalised to
// a flexible endoscope. Built once; what changes lives in ScopeState (scope_state.h).
//
// Segments are indexed from the tip (segment 0) towards the handle. Segment k spans the
// scope arclength s in [k h, (k+1) h] measured from the tip. With the tip at depth L
// (HandleInput::insertion_m) through the anus, segments with (k+1) h <= L are fully inside
// and simulated; the others are outside: straight along the entry direction, moved and
// turned by the handle (kinematic). Only the inside part is simulated, and it grows or
// shrinks as the scope is pushed or withdrawn.
//
// Material frame of a segment: the columns of R_WS are d1, d2 (up) and d3 (the axis,
// pointing distally, towards the tip), right-handed: d1 = d2 x d3, which is the LEFT of
// the image seen from the tip (the onboard camera's right is -d1, its down -d2).
#pragma once

#include <vector>

#include "core/handle_input.h"
#include "core/spline.h"

namespace colosim {

/// How the actuated joints of an active scope choose their rest bend (core/active_scope.h).
enum class ActiveStrategy {
  kFollowTheLeader,     ///< each joint takes the bend the tip had at that insertion depth
  kContactMinimising,   ///< each joint yields to the wall contact moment of its neighbourhood
};

/// An active, polyarticulated scope (the paper's SMA-driven segments, issue 20): the
/// joints from the steerable tip's end up to actuated_length_m from the tip have a rest
/// bend commanded by actuators (ScopeState::joint_rest_rad), which follows the strategy's
/// target through a first-order lag and whose moment on the joint,
/// |(EI/h) (rest - actual)| over the two bending axes, never exceeds the torque limit at a
/// step's end. Off (`enabled` false): every joint passive, the step as without it.
struct ActiveScopeParams {
  bool enabled = false;
  ActiveStrategy strategy = ActiveStrategy::kFollowTheLeader;
  double joint_torque_limit_Nm = 0.5;  ///< largest actuator bending moment per joint [N m]
  double time_constant_s = 0.05;       ///< actuator bandwidth as a first-order time constant [s]
  double actuated_length_m = 0.6;      ///< joints within this arclength from the tip are actuated [m]
  /// contact_minimising: the agent's yield rate: its rest moves at gain M / ((EI/h) tau)
  /// for a contact moment M of the loads distal of its joint [-] (the actuator's lag
  /// integrates it).
  double contact_gain = 1.0;
  /// contact_minimising: without contact the rest relaxes back to straight (passive) with
  /// this time constant [s].
  double contact_relax_s = 1.0;
};

/// A variable-stiffness section (issue 20; Olympus ScopeGuide / Innovex variable-stiffness
/// colonoscopes): the operator switches the bending stiffness EI of the joints within
/// [from_m, to_m] of arclength from the tip between levels, each a multiplier of the
/// section's own EI (stiffness profile); HandleInput::stiffness_level picks the level
/// (-1: default_level). GJ is not changed. Off: levels empty.
struct VariableStiffnessParams {
  double from_m = 0.0;               ///< start of the section, arclength from the tip [m]
  double to_m = 0.0;                 ///< end of the section, arclength from the tip [m]
  std::vector<double> levels;        ///< EI multipliers per level [-], > 0; empty: no section
  int default_level = 0;             ///< the level when the input names none
};

/// One section of the insertion tube's stiffness profile: from the previous section's end
/// (the tip for the first) to to_m, measured along the scope from the tip [m].
struct StiffnessSection {
  double to_m = 0.0;                     ///< where the section ends, arclength from the tip [m]
  double bending_stiffness_Nm2 = 0.0;    ///< EI [N m^2]
  double torsional_stiffness_Nm2 = 0.0;  ///< GJ [N m^2/rad]
};

struct ScopeParams {
  double working_length_m = 1.6;          ///< insertion tube length [m]
  double outer_diameter_m = 0.0125;       ///< [m]
  double mass_per_length_kg_per_m = 0.2;  ///< [kg/m]
  double bending_stiffness_Nm2 = 0.03;    ///< EI [N m^2]
  double torsional_stiffness_Nm2 = 0.4;   ///< GJ [N m^2/rad]
  /// EI and GJ along the scope, sections from the tip in order (a scope design's
  /// stiffness_profile, trainer/scope_design.h). Empty: bending_stiffness_Nm2 and
  /// torsional_stiffness_Nm2 over the whole length. A joint takes the section its
  /// arclength from the tip lies in (the last section reaches to the handle).
  std::vector<StiffnessSection> stiffness_profile;
  /// The knobs' stops [rad]: inputs beyond them are clamped (within the handle's
  /// kKnobUpDownMax_rad and kKnobLeftRightMax_rad).
  double knob_updown_max_rad = kKnobUpDownMax_rad;
  double knob_leftright_max_rad = kKnobLeftRightMax_rad;
  /// The angulation wires: the largest bending moment the knobs put on a joint of the
  /// bending section [N m] (the wires' tension times their offset from the axis). Within
  /// it a joint is held at the knobs' bend with its stiffness EI/h; a joint that the wall or
  /// a hooked colon bends further from the knobs' bend meets this moment and no more: the
  /// wires stretch and the thumb on the knob gives way. 0: no limit (the knobs set the
  /// bend however hard the tip is held).
  double knob_moment_limit_Nm = 0.15;
  /// The tip light: distance at which it gives unit irradiance on the mucosa, a measure of
  /// its power (render/camera.h OnboardOptics::light_ref_m) [m].
  double tip_light_reach_m = 0.02;
  double bending_section_length_m = 0.09; ///< steerable tip [m]
  double segment_length_m = 0.015;        ///< h: length of one rigid segment [m]
  double joint_stiffness_N_per_m = 2e6;   ///< penalty keeping consecutive segments joined [N/m]
  double joint_damping_s = 0.002;         ///< joint damping as a time constant: C = t K [s]
  /// The anal sphincter as a ring: the lateral stiffness with which it holds the scope
  /// where it crosses the anus (the segment straddling the anus is simulated; the ring's
  /// damping is joint_damping_s times its stiffness) [N/m]. On the straddling segment it
  /// holds with at most this, less as the segment goes in so that the segment hands its
  /// bend over from its distal joint to its proximal one across its length (core/scope_step.cc).
  double sphincter_stiffness_N_per_m = 1e6;
  double drag_Ns_per_m2 = 1.0;            ///< viscous drag per length of the inserted tube [N s/m per m]
  int slices_per_segment = 1;             ///< slices of interaction points per segment (paper Fig. 5)
  int points_per_slice = 6;               ///< interaction points around each slice
  /// Solver limits (docs/hardening.md): the largest segment speed and spin the one-step
  /// linearised solve is trusted with. 5 m/s is 5 mm per 1 ms step, a third of a segment;
  /// 250 rad/s is 0.25 rad per step, where the joints' linearised rotations (log map,
  /// right Jacobian) start to fail. Faster segments are slowed to them and counted
  /// (ScopeState::limited_segments). The handle's own 10 turns/s is 63 rad/s.
  double max_speed_m_per_s = 5.0;         ///< [m/s]
  double max_spin_rad_per_s = 250.0;      ///< [rad/s]
  /// The hand's grip on the insertion tube (docs/hardening.md): the largest axial force
  /// and torque the hand passes to the scope before the tube slides or turns in its
  /// fingers. Clinical peaks (Appleyard et al. 2000): push ~43 N, pull ~18 N, torque
  /// ~1 N m; the limits are 2.3 and 5 times those, so a clinical session never reaches
  /// them. Beyond them the outside part does not follow the handle further that step
  /// (the actual insertion and rotation lag the command: ScopeState::grip_slip_m, _rad)
  /// and the handle force and torque stay at the limits.
  double max_handle_force_N = 100.0;      ///< [N]
  double max_handle_torque_Nm = 5.0;      ///< [N m]
  /// Once the force drops, a lagging outside part catches up with the command at most
  /// this much faster than the command moves: a brisk clinical advance (1-3 cm/s)
  /// and half a turn a second.
  double grip_catch_up_m_per_s = 0.05;    ///< [m/s]
  double grip_catch_up_rad_per_s = 3.14159265358979323846;  ///< [rad/s]
  ActiveScopeParams active;               ///< actuated joints (off by default: a passive scope)
  VariableStiffnessParams variable_stiffness;  ///< operator-switched EI (off by default: levels empty)
};

struct ScopeModel {
  ScopeParams params;
  int segment_count = 0;          ///< K segments over the working length
  double h_m = 0;                 ///< segment length [m]
  double radius_m = 0;            ///< outer radius [m]
  double segment_mass_kg = 0;     ///< [kg]
  Vec3 segment_inertia_kgm2 = Vec3::Zero();  ///< principal inertia about d1, d2, d3 [kg m^2]
  /// Per joint k (between segments k and k+1, at arclength (k+1) h from the tip), K - 1 of
  /// them: (EI/h, EI/h, GJ/h) of the stiffness section the joint lies in [N m/rad].
  std::vector<Vec3> joint_stiffness_Nm_per_rad;
  int bending_joints = 0;         ///< joints 0 .. bending_joints-1 are steered by the knobs
  /// Joints first_actuated_joint .. actuated_joints-1 are actuated (active scope; joint k
  /// lies at arclength (k+1) h from the tip), their rest bend no longer the knobs'. The
  /// first is 1 for follow-the-leader (the knobs steer the tip's joint only: the leader),
  /// bending_joints for contact-minimising (the knobs steer the whole bending section).
  /// actuated_joints is 0 when the scope is passive.
  int first_actuated_joint = 0;
  int actuated_joints = 0;
  /// Joints variable_first_joint .. variable_end_joint-1 lie in the variable-stiffness
  /// section (none when the scope has none) [-].
  int variable_first_joint = 0;
  int variable_end_joint = 0;
  Vec3 p_W_anus = Vec3::Zero();   ///< the anus: fixed entry point [m]
  Mat3 R_W_entry = Mat3::Identity();  ///< scope frame at the anus at zero rotation (d3 = entry direction)
  Vec3 gravity_m_per_s2 = Vec3::Zero();
  /// Interaction points of one segment in its own frame, relative to its centre [m]:
  /// slice after slice (the last at the segment's distal end), points_per_slice each,
  /// around the circumference.
  std::vector<Vec3> interaction_points_S;
  /// Interaction points on the distal face of the tip segment (segment 0), besides its ring,
  /// in its frame [m]: the lens at the face's centre and points half way to the rim. They
  /// keep the lens out of the wall (a wall met head-on at a bend tighter than the lumen).
  /// Tracked and in contact like the others, numbered after them
  /// (WallContact::point = interaction_points_S.size() + f).
  std::vector<Vec3> tip_face_points_S;
};

/// Builds the scope model for an entry at p_W_anus along entry_direction (towards the
/// inside); `up_hint` fixes d2 at zero handle rotation. Throws std::invalid_argument for
/// non-physical parameters.
ScopeModel buildScopeModel(const ScopeParams& params, const Vec3& p_W_anus,
                           const Vec3& entry_direction, const Vec3& up_hint,
                           const Vec3& gravity_m_per_s2);

}  // namespace colosim
