#include "core/scope_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace colosim {

ScopeModel buildScopeModel(const ScopeParams& p, const Vec3& p_W_anus, const Vec3& entry,
                           const Vec3& up_hint, const Vec3& gravity) {
  if (!(p.segment_length_m > 0) || !(p.working_length_m > 2 * p.segment_length_m))
    throw std::invalid_argument("scope: the working length must exceed two segments");
  if (!(p.outer_diameter_m > 0) || !(p.mass_per_length_kg_per_m > 0) || !(p.bending_stiffness_Nm2 > 0) ||
      !(p.torsional_stiffness_Nm2 > 0) || !(p.joint_stiffness_N_per_m > 0))
    throw std::invalid_argument("scope: diameter, mass, stiffnesses must be positive");
  double previous_end_m = 0.0;
  for (const StiffnessSection& section : p.stiffness_profile) {
    if (!(section.to_m > previous_end_m) || !(section.bending_stiffness_Nm2 > 0) ||
        !(section.torsional_stiffness_Nm2 > 0))
      throw std::invalid_argument("scope: stiffness sections must follow each other with positive EI and GJ");
    previous_end_m = section.to_m;
  }
  if (!(p.knob_updown_max_rad >= 0 && p.knob_updown_max_rad <= kKnobUpDownMax_rad) ||
      !(p.knob_leftright_max_rad >= 0 && p.knob_leftright_max_rad <= kKnobLeftRightMax_rad))
    throw std::invalid_argument("scope: knob stops beyond the handle's range");
  if (!(p.knob_moment_limit_Nm >= 0 && std::isfinite(p.knob_moment_limit_Nm)))
    throw std::invalid_argument("scope: the knobs' moment limit must be finite and not negative");
  if (p.slices_per_segment < 1 || p.points_per_slice < 1)
    throw std::invalid_argument("scope: at least one slice of one interaction point");
  if (!(entry.norm() > 0)) throw std::invalid_argument("scope: entry direction is zero");

  ScopeModel m;
  m.params = p;
  m.h_m = p.segment_length_m;
  m.segment_count = static_cast<int>(std::ceil(p.working_length_m / m.h_m - 1e-9));
  m.radius_m = 0.5 * p.outer_diameter_m;
  m.segment_mass_kg = p.mass_per_length_kg_per_m * m.h_m;
  // A solid cylinder's inertia: about its axis m r^2 / 2; across it m (3 r^2 + h^2) / 12.
  const double r2 = m.radius_m * m.radius_m;
  const double i_perp = m.segment_mass_kg * (3 * r2 + m.h_m * m.h_m) / 12.0;
  m.segment_inertia_kgm2 = Vec3(i_perp, i_perp, 0.5 * m.segment_mass_kg * r2);
  m.joint_stiffness_Nm_per_rad.resize(std::max(0, m.segment_count - 1));
  for (int k = 0; k + 1 < m.segment_count; ++k) {
    double ei = p.bending_stiffness_Nm2, gj = p.torsional_stiffness_Nm2;
    const double s_m = (k + 1) * m.h_m;
    for (size_t i = 0; i < p.stiffness_profile.size(); ++i) {
      ei = p.stiffness_profile[i].bending_stiffness_Nm2;
      gj = p.stiffness_profile[i].torsional_stiffness_Nm2;
      if (s_m < p.stiffness_profile[i].to_m) break;
    }
    m.joint_stiffness_Nm_per_rad[k] = Vec3(ei / m.h_m, ei / m.h_m, gj / m.h_m);
  }
  m.bending_joints = std::max(1, static_cast<int>(std::lround(p.bending_section_length_m / m.h_m)));
  if (p.active.enabled) {
    const ActiveScopeParams& a = p.active;
    if (!(a.joint_torque_limit_Nm > 0) || !(a.time_constant_s > 0) || !(a.actuated_length_m >= 0) ||
        !std::isfinite(a.actuated_length_m) || !(a.contact_gain >= 0) ||
        !(a.contact_relax_s > 0))
      throw std::invalid_argument("scope: active joints need a positive torque limit and time constant");
    // Joint k (at (k+1) h from the tip) is actuated when it lies within the actuated length.
    m.actuated_joints = std::min(m.segment_count - 1, static_cast<int>(std::floor(a.actuated_length_m / m.h_m + 1e-9)));
    m.first_actuated_joint = a.strategy == ActiveStrategy::kFollowTheLeader ? 1 : m.bending_joints;
    m.actuated_joints = std::max(m.actuated_joints, m.first_actuated_joint);
  }
  const VariableStiffnessParams& v = p.variable_stiffness;
  if (!v.levels.empty()) {
    bool positive = true;
    for (double x : v.levels) positive = positive && x > 0 && std::isfinite(x);
    if (!positive || static_cast<int>(v.levels.size()) > kStiffnessLevelsMax || !(v.from_m >= 0) ||
        !(v.to_m > v.from_m) || v.default_level < 0 || v.default_level >= static_cast<int>(v.levels.size()))
      throw std::invalid_argument("scope: a variable-stiffness section needs from < to, positive levels and a default among them");
    // Joint k lies at (k+1) h from the tip.
    m.variable_first_joint = std::max(0, static_cast<int>(std::ceil(v.from_m / m.h_m - 1e-9)) - 1);
    m.variable_end_joint = std::min(m.segment_count - 1, static_cast<int>(std::floor(v.to_m / m.h_m + 1e-9)));
  }
  m.p_W_anus = p_W_anus;
  const Vec3 d3 = entry.normalized();
  Vec3 d2 = up_hint - up_hint.dot(d3) * d3;
  if (d2.norm() < 1e-6) d2 = d3.unitOrthogonal();
  d2.normalize();
  m.R_W_entry.col(0) = d2.cross(d3);
  m.R_W_entry.col(1) = d2;
  m.R_W_entry.col(2) = d3;
  m.gravity_m_per_s2 = gravity;

  for (int s = 0; s < p.slices_per_segment; ++s) {
    // Slices end at the segment's distal end: the tip face and every joint are covered.
    const double z = m.h_m * ((s + 1.0) / p.slices_per_segment - 0.5);
    for (int k = 0; k < p.points_per_slice; ++k) {
      const double a = 2 * M_PI * k / p.points_per_slice;
      m.interaction_points_S.emplace_back(m.radius_m * std::cos(a), m.radius_m * std::sin(a), z);
    }
  }
  // The tip face: its centre (the lens) and three points at half the radius, between the ring's.
  m.tip_face_points_S.emplace_back(0.0, 0.0, 0.5 * m.h_m);
  for (int k = 0; k < 3; ++k) {
    const double a = 2 * M_PI * (k + 0.5) / 3;
    m.tip_face_points_S.emplace_back(0.5 * m.radius_m * std::cos(a), 0.5 * m.radius_m * std::sin(a), 0.5 * m.h_m);
  }
  return m;
}

}  // namespace colosim
