#include "core/scope_kinematics.h"

#include <algorithm>
#include <cmath>

#include "core/rotation.h"
#include "core/scope_state.h"

namespace colosim {

void kinematicPose(const ScopeModel& m, int k, double L, double phi, Vec3* p, Mat3* R) {
  const Vec3 e = m.R_W_entry.col(2);
  const double s_centre = (k + 0.5) * m.h_m;
  *p = m.p_W_anus + (L - s_centre) * e;
  *R = expSO3(phi * e) * m.R_W_entry;
}

void exitPose(const ScopeModel& m, int k, double L, double phi, const Vec3& tilt_rad, const Vec3& offset_m, Vec3* p,
              Mat3* R) {
  const double kept = 1.0 - std::clamp((k * m.h_m - L) / m.h_m, 0.0, 1.0);  // of the offset when it left
  Mat3 R_straight;
  kinematicPose(m, k, L, phi, p, &R_straight);
  *R = expSO3(kept * tilt_rad) * R_straight;
  *p += kept * offset_m;
}

HandleInput clampHandleInput(const ScopeModel& m, const HandleInput& in) {
  auto finite = [](double x) { return std::isfinite(x) ? x : 0.0; };
  HandleInput c;
  const double max_insertion = (m.segment_count - 1) * m.h_m;
  c.insertion_m = std::clamp(finite(in.insertion_m), 0.0, max_insertion);
  c.rotation_rad = finite(in.rotation_rad);
  c.knob_updown_rad = std::clamp(finite(in.knob_updown_rad), -m.params.knob_updown_max_rad, m.params.knob_updown_max_rad);
  c.knob_leftright_rad =
      std::clamp(finite(in.knob_leftright_rad), -m.params.knob_leftright_max_rad, m.params.knob_leftright_max_rad);
  c.stiffness_level = std::clamp(in.stiffness_level, -1, kStiffnessLevelsMax - 1);
  return c;
}

Vec3 restJointRotation(const ScopeModel& m, int joint, const HandleInput& in) {
  if (joint >= m.bending_joints) return Vec3::Zero();
  // Up bends d3 towards d2: a rotation about d1 by -angle. Right bends d3 towards the
  // image's right, -d1: a rotation about d2 by -angle.
  const double n = m.bending_joints;
  return Vec3(-in.knob_updown_rad / n, -in.knob_leftright_rad / n, 0.0);
}

int stiffnessLevelOf(const ScopeModel& m, const HandleInput& in) {
  const VariableStiffnessParams& v = m.params.variable_stiffness;
  if (v.levels.empty()) return 0;
  if (in.stiffness_level < 0) return v.default_level;
  return std::min(in.stiffness_level, static_cast<int>(v.levels.size()) - 1);
}

double bendingStiffnessFactor(const ScopeModel& m, int joint, const HandleInput& in) {
  if (joint < m.variable_first_joint || joint >= m.variable_end_joint) return 1.0;
  return m.params.variable_stiffness.levels[stiffnessLevelOf(m, in)];
}

Vec3 tipPosition(const ScopeModel& m, const ScopeState& s) {
  return s.p_W[0] + 0.5 * m.h_m * s.R_WS[0].col(2);
}

Mat3 tipFrame(const ScopeState& s) { return s.R_WS[0]; }

}  // namespace colosim
