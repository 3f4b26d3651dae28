// Everything that changes in the colonoscope, plus the step's scratch space.
#pragma once

#include <vector>

#include "core/block_tridiagonal.h"
#include "core/handle_input.h"
#include "core/scope_kinematics.h"
#include "core/scope_model.h"

namespace colosim {

/// A load on one scope segment at a point of it (a wall contact): force, and the
/// stiffness and damping of that force with respect to the point's motion.
struct ScopeLoad {
  int segment = 0;
  Vec3 r_W = Vec3::Zero();                ///< lever: point minus segment centre, world [m]
  Vec3 force_N = Vec3::Zero();            ///< force on the scope at the point [N]
  Mat3 stiffness_N_per_m = Mat3::Zero();  ///< -dF/dx (symmetric PSD)
  Mat3 damping_Ns_per_m = Mat3::Zero();   ///< -dF/dv (symmetric PSD)
};

/// What the handle feels: the force and torque the operator must apply to move the handle
/// as commanded (quasi-static: the handle's own inertia is not included).
struct HandleReaction {
  double force_N = 0;      ///< axial force, positive when pushing in [N]
  double torque_Nm = 0;    ///< axial torque, positive clockwise as seen by the operator [N m]
  Vec3 force_W = Vec3::Zero();   ///< full force the scope exerts on the anus/handle, world [N]
};

struct ScopeState {
  std::vector<Vec3> p_W;   ///< segment centres (K) [m]
  std::vector<Mat3> R_WS;  ///< segment frames (K): columns d1, d2, d3
  std::vector<Vec3> v_W;   ///< segment centre velocities (K) [m/s]
  std::vector<Vec3> w_W;   ///< segment angular velocities, world (K) [rad/s]
  int inside = 0;          ///< segments wholly inside the body: 0 .. inside-1
  /// Simulated segments: 0 .. simulated-1, the ones inside and the one straddling the anus
  /// (held there by the sphincter, a ring: see core/scope_step.h); the rest are kinematic.
  int simulated = 0;
  /// The first kinematic segment when it left the chain off its straight pose (withdrawn),
  /// else -1: it comes out straightening as it does (see exitPose()).
  int tilted_segment = -1;
  Vec3 tilt_rad = Vec3::Zero();    ///< its rotation from the straight pose when it left: a world rotation vector [rad]
  Vec3 tilt_offset_m = Vec3::Zero();  ///< its centre's offset from the straight pose when it left, world [m]
  HandleInput input;       ///< the outside part's pose after the last step: the handle inputs, clamped, less the grip slip
  double grip_slip_m = 0;    ///< commanded minus actual insertion: how far the grip has slipped along the tube [m]
  double grip_slip_rad = 0;  ///< commanded minus actual rotation [rad]
  double time_s = 0;       ///< [s]
  std::vector<ScopeLoad> loads;  ///< loads for the next step (cleared by the caller)
  /// The lens guard (a unilateral constraint on the lens, core/scope_step.h): the wall the
  /// lens faces, set by the caller before each step like the loads; active false: no guard.
  struct LensWall {
    bool active = false;
    Vec3 n_W = Vec3::UnitX();      ///< outward wall normal at the lens (centreline to lens) [-]
    double gap_m = 0;              ///< how far the lens may still move along n_W this step [m]
    double wall_speed_m_per_s = 0; ///< the wall's velocity along n_W [m/s]
  } lens_wall;
  /// The guard's impulse on the lens in the last step, along -lens_wall.n_W (0: not
  /// engaged); the caller passes its reaction to the wall [N s].
  double lens_impulse_Ns = 0;
  HandleReaction handle;   ///< reaction after the last step
  Vec3 sphincter_force_W = Vec3::Zero();  ///< the sphincter's force on the scope after the last step, world [N]
  bool solver_ok = true;   ///< false when the last solve failed or gave non-finite values (velocities then zeroed)
  int limited_segments = 0;        ///< segments slowed to the speed or spin limit in the last step
  double asked_speed_m_per_s = 0;  ///< largest segment speed the last solve asked for, before limiting [m/s]
  double asked_spin_rad_per_s = 0; ///< largest segment spin the last solve asked for, before limiting [rad/s]
  bool grip_limited = false;         ///< the handle force or torque limit engaged in the last step (the grip slipped)
  double asked_handle_force_N = 0;   ///< handle force the commanded motion asked for in the last step [N]
  double asked_handle_torque_Nm = 0; ///< handle torque the commanded motion asked for in the last step [N m]

  /// The scope has a variable-stiffness section: the snapshot then holds input.stiffness_level.
  bool has_stiffness_levels = false;

  // The active scope (ScopeParams::active; core/active_scope.h). Empty when it is off.
  /// Commanded rest rotation of each joint (K, joint k between segments k and k+1) in the
  /// joint frame, the actuators' output; only the actuated joints' entries are used [rad].
  std::vector<Vec3> joint_rest_rad;
  /// The lead: the bend of the tip's joint (joint 0: the knobs' rest rotation, joint frame)
  /// when the insertion was j h [rad], samples j = 0 .. lead_count-1 (K). Kept when the
  /// scope is withdrawn; a sample is taken again whenever the insertion passes j h going in.
  std::vector<Vec3> lead_bend_rad;
  int lead_count = 0;

  // Scratch, sized by makeScopeState() so that the step allocates nothing.
  /// Active contact-minimising scope: per segment, the sum of its contact forces [N] and of
  /// their moments about the patient frame's origin [N m] (updateActiveScope).
  std::vector<Vec3> segment_load_force_N, segment_load_moment_Nm;
  BlockTridiagonal<6> system;  ///< 6 unknowns per segment; joints couple neighbours
  Eigen::VectorXd rhs;
  Eigen::VectorXd force;
  Eigen::VectorXd guard_response;  ///< the chain's velocity change per unit impulse on the lens (or a threading stop)
  /// The state at the start of the step, to step again from when the grip slips (the
  /// fields a step changes before the grip: saveStart() and restoreStart() copy them).
  struct Start {
    std::vector<Vec3> p_W, v_W, w_W;
    std::vector<Mat3> R_WS;
    int inside = 0;
    int simulated = 0;
    int tilted_segment = -1;
    Vec3 tilt_rad = Vec3::Zero();
    Vec3 tilt_offset_m = Vec3::Zero();
    HandleInput input;
    double time_s = 0;
  } start;
};

/// The scope withdrawn (tip at the anus), with scratch sized for the model.
ScopeState makeScopeState(const ScopeModel& model, int load_capacity = 4096);

/// Copies the fields of ScopeState::Start from the state into state.start (saveStart) or
/// back (restoreStart). Allocates nothing.
void saveStart(ScopeState& state);
void restoreStart(ScopeState& state);

/// Flat snapshot of the physical state, and its restoration (same model).
std::vector<double> getScopeState(const ScopeState& state);
void setScopeState(const std::vector<double>& snapshot, ScopeState& state);

}  // namespace colosim
