#include "core/world.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/rotation.h"

#include "core/colon_step.h"
#include "core/colon_threading.h"
#include "core/scope_step.h"
#include "core/step_lanes.h"

namespace colosim {

namespace {

// The lens guard's wall: the tip slice's tracked location (the lens is the centre of the
// tip segment's last slice, at the face), its outward normal towards the lens, the gap
// left to the wall less the margin, and the wall's speed along the normal.
void setLensWall(const WorldModel& m, WorldState& s) {
  ScopeState::LensWall& wall = s.scope.lens_wall;
  wall.active = false;
  s.lens_wall_segment = -1;
  const int slices = m.scope.params.slices_per_segment;
  if (s.scope.inside == 0 || m.contact.lens_margin_m < 0 || m.scope.tip_face_points_S.empty()) return;
  const WallTrack& t = s.slice_track[static_cast<size_t>(slices) - 1];
  if (t.colon_segment < 0) return;
  const Vec3 lens = tipFacePoint(m.scope, s.scope, 0);
  const Vec3 d = lens - splinePoint(s.colon.q, t.colon_segment, t.p);
  const double dist = d.norm();
  if (!(dist > 1e-9)) return;
  wall.n_W = d / dist;
  wall.gap_m = m.colon.radiusAt(t.colon_segment, t.p) - dist - m.contact.lens_margin_m;
  wall.wall_speed_m_per_s = apply(blend(m.colon.n, t.colon_segment, t.p, 0), s.colon.v).dot(wall.n_W);
  wall.active = std::isfinite(wall.gap_m) && std::isfinite(wall.wall_speed_m_per_s);
  if (wall.active) s.lens_wall_segment = t.colon_segment, s.lens_wall_p = t.p;
}

// Whether the lens could reach its wall within the step: its gap is less than the lens
// and the wall can close at their speed limits (the scope segment's speed and spin about
// the lens's arm, the colon's control points). Only then does the guard need the wall's
// speed over the step itself, which the colon's step gives.
bool lensMayReachWall(const WorldModel& m, const WorldState& s, double dt) {
  const ScopeState::LensWall& wall = s.scope.lens_wall;
  if (!wall.active) return false;
  const double arm_m = m.scope.tip_face_points_S[0].norm();
  const double closing_m_per_s =
      m.scope.params.max_speed_m_per_s + m.scope.params.max_spin_rad_per_s * arm_m + m.colon.max_speed_m_per_s;
  return wall.gap_m < closing_m_per_s * dt;
}

// The lens wall's speed along its normal over the step, from the colon's velocity after its
// step (the spline point at a fixed parameter moves by dt times that blend, exactly).
void setLensWallSpeedFromColonStep(const WorldModel& m, WorldState& s) {
  ScopeState::LensWall& wall = s.scope.lens_wall;
  const double speed = apply(blend(m.colon.n, s.lens_wall_segment, s.lens_wall_p, 0), s.colon.v).dot(wall.n_W);
  if (std::isfinite(speed)) wall.wall_speed_m_per_s = speed;
}

void saveColonStart(WorldState& s) {
  s.colon_start.q = s.colon.q;
  s.colon_start.v = s.colon.v;
  s.colon_start.time_s = s.colon.time_s;
  s.colon_start.tension_internal = s.colon.tension_internal;
}

void restoreColonStart(WorldState& s) {
  s.colon.q = s.colon_start.q;
  s.colon.v = s.colon_start.v;
  s.colon.time_s = s.colon_start.time_s;
  s.colon.tension_internal = s.colon_start.tension_internal;
}

// The step's loads on both bodies from the contacts found at its start (and, for a
// correction, the previous sweep's end: ContactParams::coupling_sweeps), the support and the
// lens guard's wall; the colon's start state kept for the guard's second colon step.
void loadBothBodies(const WorldModel& m, WorldState& s, double dt, const CouplingSweep* previous) {
  s.colon.loads.clear();
  s.scope.loads.clear();
  s.max_wall_force_N = applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, s.wall, s.colon.loads,
                                         s.scope.loads, &s.contact_limit, m.contact.coupling_predictor ? dt : 0.0,
                                         previous, &s.coupling_stiffness);
  applyThreadingContacts(m, s, dt, previous);
  applySelfContacts(m.contact, m.colon, s.colon, s.self, s.colon.loads);
  for (const RegionSupport& r : s.support) addRegionSupport(m.colon, s.colon, r, s.colon.loads);
  setLensWall(m, s);
  saveColonStart(s);
}

// The lens guard held the lens: the wall takes the reaction over the same step.
void stepColonWithLensReaction(const WorldModel& m, WorldState& s, double dt) {
  if (!(s.scope.lens_impulse_Ns > 0 && s.lens_wall_segment >= 0)) return;
  restoreColonStart(s);
  SplineLoad l;
  l.segment = s.lens_wall_segment;
  l.p = s.lens_wall_p;
  l.force_N = (s.scope.lens_impulse_Ns / dt) * s.scope.lens_wall.n_W;
  s.colon.loads.push_back(l);
  stepColon(m.colon, s.colon, dt);
}

// Both bodies' solves on one lane: the colon's first, so that the lens guard, when the lens
// may reach its wall, takes the wall's speed from the colon's step.
void solveBothOnOneLane(const WorldModel& m, WorldState& s, const HandleInput& in, double dt, bool lens_near) {
  stepColon(m.colon, s.colon, dt);
  if (lens_near) setLensWallSpeedFromColonStep(m, s);
  stepScope(m.scope, s.scope, in, dt);
}

// ContactParams::coupling_sweeps: the step solved, then solved again from its start state
// with each contact carrying the other body's move of the previous sweep, on one lane.
void stepWithCouplingSweeps(const WorldModel& m, WorldState& s, const HandleInput& in, double dt) {
  const ScopeState scope_start = s.scope;
  const ColonState colon_start = s.colon;
  for (int sweep = 0; sweep <= m.contact.coupling_sweeps; ++sweep) {
    if (sweep > 0) {
      const ScopeState scope_end = s.scope;
      const ColonState colon_end = s.colon;
      s.scope = scope_start;
      s.colon = colon_start;
      const CouplingSweep previous{&scope_end, &colon_end};
      loadBothBodies(m, s, dt, &previous);
    }
    solveBothOnOneLane(m, s, in, dt, lensMayReachWall(m, s, dt));
  }
  stepColonWithLensReaction(m, s, dt);
  stopThreading(m, s, dt);
}

}  // namespace

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
  const size_t points = m.scope.segment_count * m.scope.interaction_points_S.size() + m.scope.tip_face_points_S.size();
  s.track.assign(points, WallTrack());
  s.slice_track.assign(static_cast<size_t>(m.scope.segment_count) * m.scope.params.slices_per_segment, WallTrack());
  s.wall.reserve(points);
  s.self.reserve(16 * m.colon.n);
  s.threading.reserve(4 * static_cast<size_t>(m.colon.n));
  s.threading_near.reserve(4 * static_cast<size_t>(m.colon.n));
  s.threading_stops.reserve(4 * static_cast<size_t>(m.colon.n));
  s.colon_start.q = s.colon.q;
  s.colon_start.v = s.colon.v;
  s.colon_start.tension_internal = s.colon.tension_internal;
  s.coupling_stiffness.scope_segment_N_per_m.setZero(m.scope.segment_count);
  s.coupling_stiffness.colon_point_N_per_m.setZero(m.colon.n);
  return s;
}

void stepWorld(const WorldModel& m, WorldState& s, const HandleInput& in, ContactQuery& q, double dt,
               StepLanes* lanes) {
  // Broadphase and narrowphase: contacts of the state at the start of the step.
  if (lanes) {
    lanes->run([&] { q.findSelfContacts(m, s); }, [&] { q.findWallContacts(m, s); });
  } else {
    q.findWallContacts(m, s);
    q.findSelfContacts(m, s);
  }
  // Forces: each contact loads both bodies, with its stiffness for the implicit solves.
  loadBothBodies(m, s, dt, nullptr);
  if (m.contact.coupling_sweeps > 0) {
    stepWithCouplingSweeps(m, s, in, dt);
    return;
  }
  // Solve and integrate, each body with the other's part of the contact forces held over the
  // step or carried at its start velocity (ContactParams::coupling_predictor). The
  // colon's step does not depend on the scope's; when the lens may reach its wall, the
  // scope's step waits for the colon's, so that the guard stops the lens at where the wall
  // will be, not at where the wall's velocity at the start would take it (a colon dragged
  // along decelerates within the step: 0.3-1.1 m/s apart in extreme_all's push).
  const bool lens_near = lensMayReachWall(m, s, dt);
  if (lanes && !lens_near) {
    lanes->run([&] { stepColon(m.colon, s.colon, dt); }, [&] { stepScope(m.scope, s.scope, in, dt); });
  } else if (lanes) {
    // The scope's step needs the wall's speed from the colon's step only at its lens guard,
    // after its forces and factorisation: it waits there for the flag. The colon's step runs
    // on the caller's lane, so the flag is set even when the worker is late (the caller
    // then takes the scope's step back after setting it).
    std::atomic<bool> wall_speed_ready{false};
    lanes->run([&] { stepScope(m.scope, s.scope, in, dt, &wall_speed_ready); },
               [&] {
                 stepColon(m.colon, s.colon, dt);
                 setLensWallSpeedFromColonStep(m, s);
                 wall_speed_ready.store(true, std::memory_order_release);
               });
  } else {
    solveBothOnOneLane(m, s, in, dt, lens_near);
  }
  stepColonWithLensReaction(m, s, dt);
  // The threading stops, on both bodies' solved steps.
  stopThreading(m, s, dt);
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
  sc.simulated = sc.inside + 1 < scope.segment_count && depth > 0 ? sc.inside + 1 : sc.inside;
  sc.tilted_segment = -1;
  sc.tilt_rad.setZero();
  sc.tilt_offset_m.setZero();
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
  // The joints lie on the centreline, each one chord of exactly h after the one before it,
  // from the distal end of the first segment outside (on the entry axis, at the anus) to
  // the tip: consecutive segments meet, so the joints start closed. (Segments centred on
  // chords of arclength h were shorter than h apart and overlapped at every bend: a
  // start-up kick of ~384 N in the joints.) The tip therefore lies a little deeper along
  // the colon than the insertion, by what the bends take.
  Vec3 a = sc.p_W[sc.inside] + 0.5 * scope.h_m * sc.R_WS[sc.inside].col(2);
  double arc_a = depth - sc.inside * scope.h_m;  // arclength of the centreline point nearest a [m]
  for (int k = sc.inside - 1; k >= 0; --k) {
    // The first arclength past arc_a whose centreline point is h from a: march in eighths
    // of h, then bisect (lo stays nearer than h, hi at h or beyond).
    const double step = 0.125 * scope.h_m;
    double lo = arc_a, hi = arc_a;
    while (hi < s_at.back() && (pointAt(hi) - a).norm() < scope.h_m) {
      lo = hi;
      hi = std::min(hi + step, s_at.back());
    }
    if ((pointAt(hi) - a).norm() >= scope.h_m)
      for (int it = 0; it < 50; ++it) {
        const double mid = 0.5 * (lo + hi);
        ((pointAt(mid) - a).norm() < scope.h_m ? lo : hi) = mid;
      }
    const Vec3 d = pointAt(hi) - a;
    const Vec3 axis = d.norm() > 1e-12 ? Vec3(d / d.norm()) : Vec3(R.col(2));
    const Vec3 b = a + scope.h_m * axis;
    const Vec3 prev = R.col(2);
    const Vec3 c = prev.cross(axis);
    const double sn = c.norm(), cs = prev.dot(axis);
    if (sn > 1e-12) R = expSO3(c / sn * std::atan2(sn, cs)) * R;
    sc.R_WS[k] = R;
    sc.p_W[k] = 0.5 * (a + b);
    a = b;
    arc_a = hi;
  }
  // An active scope starts passive, its lead taken from the shaft at its first step.
  std::fill(sc.joint_rest_rad.begin(), sc.joint_rest_rad.end(), Vec3::Zero());
  if (!sc.lead_bend_rad.empty()) sc.lead_count = 1;
  for (WallTrack& t : s.track) t = WallTrack();
  for (WallTrack& t : s.slice_track) t = WallTrack();
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
  for (const std::vector<WallTrack>* tracks : {&s.track, &s.slice_track})
    for (const WallTrack& t : *tracks) {
      mix(&t.colon_segment, sizeof t.colon_segment);
      mix(&t.p, sizeof t.p);
    }
  for (const RegionSupport& r : s.support)  // abdominal pressure anchors (none: the hash is unchanged)
    if (r.anchor_q.size() > 0) mix(r.anchor_q.data(), r.anchor_q.size() * sizeof(double));
  return h;
}

}  // namespace colosim
