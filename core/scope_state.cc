#include "core/scope_state.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace colosim {

ScopeState makeScopeState(const ScopeModel& m, int load_capacity) {
  ScopeState s;
  const int K = m.segment_count;
  s.p_W.resize(K);
  s.R_WS.resize(K);
  s.v_W.assign(K, Vec3::Zero());
  s.w_W.assign(K, Vec3::Zero());
  for (int k = 0; k < K; ++k) kinematicPose(m, k, 0.0, 0.0, &s.p_W[k], &s.R_WS[k]);
  s.inside = 0;
  s.loads.reserve(load_capacity);
  s.system.resize(K);
  s.rhs = Eigen::VectorXd::Zero(6 * K);
  s.force = Eigen::VectorXd::Zero(6 * K);
  s.guard_response = Eigen::VectorXd::Zero(6 * K);
  s.has_stiffness_levels = !m.params.variable_stiffness.levels.empty();
  if (m.params.active.enabled) {
    s.joint_rest_rad.assign(K, Vec3::Zero());
    s.lead_bend_rad.assign(K, Vec3::Zero());
    s.lead_count = 1;  // the tip at the anus, along the entry
    s.segment_load_force_N.assign(K, Vec3::Zero());
    s.segment_load_moment_Nm.assign(K, Vec3::Zero());
  }
  s.start.p_W = s.p_W;
  s.start.R_WS = s.R_WS;
  s.start.v_W = s.v_W;
  s.start.w_W = s.w_W;
  return s;
}

namespace {

// The one list of the fields of ScopeState::Start, copied from `a` to `b` (either way
// between a state and its start; the per-segment arrays are copied in place, sized alike).
template <class From, class To>
void copyStartFields(const From& a, To& b) {
  std::copy(a.p_W.begin(), a.p_W.end(), b.p_W.begin());
  std::copy(a.R_WS.begin(), a.R_WS.end(), b.R_WS.begin());
  std::copy(a.v_W.begin(), a.v_W.end(), b.v_W.begin());
  std::copy(a.w_W.begin(), a.w_W.end(), b.w_W.begin());
  b.inside = a.inside;
  b.simulated = a.simulated;
  b.tilted_segment = a.tilted_segment;
  b.tilt_rad = a.tilt_rad;
  b.tilt_offset_m = a.tilt_offset_m;
  b.input = a.input;
  b.time_s = a.time_s;
}

constexpr size_t kSnapshotHeader = 16;  // time, inside, simulated, tilted segment, tilt (3), tilt offset (3), inputs (4), grip slip (2)

// The active scope's part of the snapshot, after the segments (none when it is off, so a
// passive scope's snapshot and hash are as before): lead count, then per joint its rest
// rotation and the lead's bend (6 values each).
// Then, on a scope with a variable-stiffness section, the stiffness level of the input.
size_t activeSnapshotSize(const ScopeState& s) {
  return (s.joint_rest_rad.empty() ? 0 : 1 + 6 * s.joint_rest_rad.size()) + (s.has_stiffness_levels ? 1 : 0);
}

}  // namespace

void saveStart(ScopeState& s) { copyStartFields(s, s.start); }

void restoreStart(ScopeState& s) { copyStartFields(s.start, s); }

std::vector<double> getScopeState(const ScopeState& s) {
  std::vector<double> out;
  const size_t K = s.p_W.size();
  out.reserve(kSnapshotHeader + K * 18 + activeSnapshotSize(s));
  out.push_back(s.time_s);
  out.push_back(s.inside);
  out.push_back(s.simulated);
  out.push_back(s.tilted_segment);
  out.insert(out.end(), s.tilt_rad.data(), s.tilt_rad.data() + 3);
  out.insert(out.end(), s.tilt_offset_m.data(), s.tilt_offset_m.data() + 3);
  out.push_back(s.input.insertion_m);
  out.push_back(s.input.rotation_rad);
  out.push_back(s.input.knob_updown_rad);
  out.push_back(s.input.knob_leftright_rad);
  out.push_back(s.grip_slip_m);
  out.push_back(s.grip_slip_rad);
  for (size_t k = 0; k < K; ++k) {
    out.insert(out.end(), s.p_W[k].data(), s.p_W[k].data() + 3);
    out.insert(out.end(), s.R_WS[k].data(), s.R_WS[k].data() + 9);
    out.insert(out.end(), s.v_W[k].data(), s.v_W[k].data() + 3);
    out.insert(out.end(), s.w_W[k].data(), s.w_W[k].data() + 3);
  }
  if (!s.joint_rest_rad.empty()) {
    out.push_back(s.lead_count);
    for (size_t k = 0; k < s.joint_rest_rad.size(); ++k)
      for (const Vec3* v : {&s.joint_rest_rad[k], &s.lead_bend_rad[k]}) out.insert(out.end(), v->data(), v->data() + 3);
  }
  if (s.has_stiffness_levels) out.push_back(s.input.stiffness_level);
  return out;
}

void setScopeState(const std::vector<double>& snap, ScopeState& s) {
  const size_t K = s.p_W.size();
  const size_t expected = kSnapshotHeader + K * 18 + activeSnapshotSize(s);
  if (snap.size() != expected)
    throw std::invalid_argument("scope state snapshot has " + std::to_string(snap.size()) +
                                " values, expected " + std::to_string(expected));
  size_t i = 0;
  s.time_s = snap[i++];
  s.inside = static_cast<int>(snap[i++]);
  s.simulated = static_cast<int>(snap[i++]);
  s.tilted_segment = static_cast<int>(snap[i++]);
  std::memcpy(s.tilt_rad.data(), &snap[i], 3 * sizeof(double)); i += 3;
  std::memcpy(s.tilt_offset_m.data(), &snap[i], 3 * sizeof(double)); i += 3;
  s.input.insertion_m = snap[i++];
  s.input.rotation_rad = snap[i++];
  s.input.knob_updown_rad = snap[i++];
  s.input.knob_leftright_rad = snap[i++];
  s.grip_slip_m = snap[i++];
  s.grip_slip_rad = snap[i++];
  for (size_t k = 0; k < K; ++k) {
    std::memcpy(s.p_W[k].data(), &snap[i], 3 * sizeof(double)); i += 3;
    std::memcpy(s.R_WS[k].data(), &snap[i], 9 * sizeof(double)); i += 9;
    std::memcpy(s.v_W[k].data(), &snap[i], 3 * sizeof(double)); i += 3;
    std::memcpy(s.w_W[k].data(), &snap[i], 3 * sizeof(double)); i += 3;
  }
  if (!s.joint_rest_rad.empty()) {
    s.lead_count = static_cast<int>(snap[i++]);
    for (size_t k = 0; k < s.joint_rest_rad.size(); ++k)
      for (Vec3* v : {&s.joint_rest_rad[k], &s.lead_bend_rad[k]}) {
        std::memcpy(v->data(), &snap[i], 3 * sizeof(double));
        i += 3;
      }
  }
  if (s.has_stiffness_levels) s.input.stiffness_level = static_cast<int>(snap[i++]);
}

}  // namespace colosim
