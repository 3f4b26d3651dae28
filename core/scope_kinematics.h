// Scope kinematics: where the handle puts the part outside the patient, the knobs' rest
// bend of the steerable tip, the clamping of handle inputs and the tip's pose. Free
// functions of the model (and, for the tip, the state): no dynamics here.
#pragma once

#include "core/handle_input.h"
#include "core/scope_model.h"

namespace colosim {

struct ScopeState;

/// The pose of segment k when it is outside (kinematic): straight along the entry
/// direction at insertion depth L [m], turned by the handle rotation phi [rad].
/// p_W = p_anus + (L - (k + 1/2) h) e,  R_WS = exp(phi e) R_entry,  e = R_entry d3.
void kinematicPose(const ScopeModel& model, int k, double insertion_m, double rotation_rad,
                   Vec3* p_W, Mat3* R_WS);

/// The pose of segment k when it is the first kinematic segment and left the simulated
/// chain (withdrawn) off its straight pose: turned by `tilt_rad` (a world rotation vector,
/// applied after the handle's turn, so that turning the handle spins the segment about its
/// own axis) [rad] and with its centre offset by `offset_m` (world) [m]. Both fade linearly
/// over the next segment length of withdrawal, from all of them when its distal end is at
/// the anus (insertion k h, where it left) to none at insertion (k - 1) h, where it matches
/// kinematicPose(). So a segment leaves the chain where the chain put it.
void exitPose(const ScopeModel& model, int k, double insertion_m, double rotation_rad, const Vec3& tilt_rad,
              const Vec3& offset_m, Vec3* p_W, Mat3* R_WS);

/// Clamps handle inputs into the scope's ranges (insertion within the working length,
/// knobs within their stops, the stiffness level within -1 .. kStiffnessLevelsMax - 1); NaN becomes 0.
HandleInput clampHandleInput(const ScopeModel& model, const HandleInput& in);

/// Rest relative rotation of joint k (between segment k and k+1) for the knob angles [rad]:
/// each of the model.bending_joints joints of the steerable tip takes 1/n of the knob angles.
Vec3 restJointRotation(const ScopeModel& model, int joint, const HandleInput& in);

/// The factor on the bending stiffness EI of joint k for the input's stiffness level: the
/// level's multiplier in the variable-stiffness section (level -1: the default level; past
/// the last: the last), 1 elsewhere and on a scope without one.
double bendingStiffnessFactor(const ScopeModel& model, int joint, const HandleInput& in);

/// The stiffness level in effect for the input: an index into the section's levels (0 on a
/// scope without a variable-stiffness section).
int stiffnessLevelOf(const ScopeModel& model, const HandleInput& in);

/// Tip position [m] and frame (the tip segment's material frame; the camera looks along d3).
Vec3 tipPosition(const ScopeModel& model, const ScopeState& state);
Mat3 tipFrame(const ScopeState& state);

}  // namespace colosim
