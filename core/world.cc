#include "core/world.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/rotation.h"

#include "core/colon_step.h"
#include "core/scope_step.h"

namespace colosim {

WorldModel makeWorldModel(ColonModel colon, const ScopeParams& scope, const ContactParams& contact) {
  WorldModel m;
  const Vec3 anus = colon.q_rest.col(0);
  const Vec3 entry = splineTangent(colon.q_rest, 0, 0.0);
  m.scope = buildScopeModel(scope, anus, entry, Vec3(0, -1, 0), colon.gravity_m_per_s2);
  m.colon = std::move(colon);
  m.contact = contact;
  return m;
}

WorldState makeWorldState(const WorldModel& m) {
  WorldState s;
  s.colon = makeColonState(m.colon, 8192);
  s.scope = makeScopeState(m.scope);
  const size_t points = m.scope.segment_count * m.scope.interaction_points_S.size();
  s.track.assign(points, WallTrack());
  s.wall.reserve(points);
  s.self.reserve(16 * m.colon.n);
  return s;
}

void stepWorld(const WorldModel& m, WorldState& s, const HandleInput& in, ContactQuery& q, double dt) {
  // Broadphase and narrowphase: contacts of the state at the start of the step.
  q.findWallContacts(m, s);
  q.findSelfContacts(m, s);
  // Forces: each contact loads both bodies, with its stiffness for the implicit solves.
  s.colon.loads.clear();
  s.scope.loads.clear();
  s.max_wall_force_N = applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, s.wall,
                                         s.colon.loads, s.scope.loads, &s.contact_limit);
  applySelfContacts(m.contact, m.colon, s.colon, s.self, s.colon.loads);
  for (const RegionSupport& r : s.support) addRegionSupport(m.colon, s.colon, r, s.colon.loads);
  // Solve and integrate, each body with the other's contact forces held over the step.
  stepColon(m.colon, s.colon, dt);
  stepScope(m.scope, s.scope, in, dt);
}

void threadScopeAlongColon(const WorldModel& m, WorldState& s, double insertion_m, double rotation_rad) {
  const ColonModel& colon = m.colon;
  const ScopeModel& scope = m.scope;
  // Arclength along the current centreline at each control point.
  std::vector<double> s_at(colon.n, 0.0);
  for (int j = 0; j + 1 < colon.n; ++j) s_at[j + 1] = s_at[j] + segmentArclength(s.colon.q, j);
  const double depth = std::clamp(insertion_m, 0.0, std::min(s_at.back(), (scope.segment_count - 1) * scope.h_m));
  auto pointAt = [&](double arc) {
    arc = std::clamp(arc, 0.0, s_at.back());
    int j = static_cast<int>(std::upper_bound(s_at.begin(), s_at.end(), arc) - s_at.begin()) - 1;
    j = std::clamp(j, 0, colon.n - 2);
    return splinePoint(s.colon.q, j, parameterAtArclength(s.colon.q, j, arc - s_at[j]));
  };
  HandleInput in;
  in.insertion_m = depth;
  in.rotation_rad = rotation_rad;
  ScopeState& sc = s.scope;
  sc.input = in;
  sc.grip_slip_m = sc.grip_slip_rad = 0;
  sc.inside = std::min(scope.segment_count - 1, static_cast<int>(std::floor(depth / scope.h_m + 1e-9)));
  sc.tilted_segment = -1;
  sc.tilt_rad.setZero();
  // Frames carried along the centreline by the rotation between consecutive axes
  // (parallel transport), starting from the entry frame turned by the handle.
  Mat3 R;
  Vec3 p;
  kinematicPose(scope, sc.inside, depth, rotation_rad, &p, &R);
  for (int k = 0; k < scope.segment_count; ++k) {
    sc.v_W[k].setZero();
    sc.w_W[k].setZero();
    if (k >= sc.inside) kinematicPose(scope, k, depth, rotation_rad, &sc.p_W[k], &sc.R_WS[k]);
  }
  for (int k = sc.inside - 1; k >= 0; --k) {
    const double s_prox = depth - (k + 1) * scope.h_m, s_dist = depth - k * scope.h_m;
    const Vec3 a = pointAt(s_prox), b = pointAt(s_dist);
    const Vec3 axis = (b - a).normalized();
    const Vec3 prev = R.col(2);
    const Vec3 c = prev.cross(axis);
    const double sn = c.norm(), cs = prev.dot(axis);
    if (sn > 1e-12) R = expSO3(c / sn * std::atan2(sn, cs)) * R;
    sc.R_WS[k] = R;
    sc.p_W[k] = 0.5 * (a + b);
  }
  for (WallTrack& t : s.track) t = WallTrack();
}

int limitedCount(const WorldState& s) {
  return s.contact_limit.limited + s.contact_limit.non_finite + s.colon.limited_points + s.scope.limited_segments +
         (s.colon.solver_ok ? 0 : 1) + (s.scope.solver_ok ? 0 : 1) + (s.scope.grip_limited ? 1 : 0);
}

uint64_t hashWorldState(const WorldState& s) {
  uint64_t h = hashColonState(s.colon);
  auto mix = [&h](const void* data, size_t bytes) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) {
      h ^= p[i];
      h *= 1099511628211ull;
    }
  };
  const std::vector<double> scope = getScopeState(s.scope);
  mix(scope.data(), scope.size() * sizeof(double));
  for (const WallTrack& t : s.track) {
    mix(&t.colon_segment, sizeof t.colon_segment);
    mix(&t.p, sizeof t.p);
  }
  for (const RegionSupport& r : s.support)  // abdominal pressure anchors (none: the hash is unchanged)
    if (r.anchor_q.size() > 0) mix(r.anchor_q.data(), r.anchor_q.size() * sizeof(double));
  return h;
}

}  // namespace colosim
