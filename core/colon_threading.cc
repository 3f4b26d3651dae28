#include "core/colon_threading.h"

#include <algorithm>
#include <cmath>

#include "core/rotation.h"

namespace colosim {

namespace {

/// A slice of the chain from the anus to the tip: its scope segment, its place along the
/// colon (segment + p) and its centre [m].
struct ChainNode {
  int segment = 0;
  double track = 0;
  Vec3 centre = Vec3::Zero();
};

/// How far along the colon a threading contact is handed over at an end of the chain
/// [control-point spacings]: a control point that the slice at the chain's end has only
/// just passed is held with a weight growing from 0 to 1 over this much of the slice's
/// further travel, where a full-strength contact would appear at once as deep as the slice
/// came (the tip pressing the wall ahead of it: 0.7 mm, 22 N in one step).
constexpr double kEndHandOver = 0.5;

/// The point of segment x-y nearest to q, and its fraction along the segment.
Vec3 nearestOnSegment(const Vec3& x, const Vec3& y, const Vec3& q, double& w) {
  const Vec3 d = y - x;
  const double dd = d.squaredNorm();
  w = dd > 0 ? std::clamp((q - x).dot(d) / dd, 0.0, 1.0) : 0.0;
  return x + w * d;
}

/// The threading contacts of the control points whose places lie between consecutive
/// chain nodes a and b. `before` and `after` are the chain's nodes next to them (null at an
/// end of the chain). The scope's axis at control point i is the point of the chain's
/// polyline nearest q_i among the chord a-b and its neighbours before-a and b-after: the
/// distance to that union of chords, which is what the depth reads, moves continuously as
/// a track passes i or flips for a step among control points a gathered colon has brought
/// within millimetres of one slice (session 23: tracks flipping 11.97 -> 9.999 at the
/// rectosigmoid junction; with the axis interpolated by track the contact jumped 1-2 mm,
/// 20-36 N). `first_chord`, `last_chord`: the chord is at an end of its chain (the
/// hand-over above).
void chordContacts(const WorldModel& m, const WorldState& s, const ChainNode* before, const ChainNode& a,
                   const ChainNode& b, const ChainNode* after, bool first_chord, bool last_chord,
                   double margin_m, std::vector<WallContact>& out) {
  const int n = m.colon.n;
  const double behind_m = m.contact.wall_thickness_m - m.scope.radius_m;  // added to r_i [m]
  const double ta = a.track, tb = b.track;
  const int first = std::max(1, static_cast<int>(std::floor(std::min(ta, tb))) + 1);
  const int last = std::min(n - 2, static_cast<int>(std::ceil(std::max(ta, tb))) - 1);
  for (int i = first; i <= last; ++i) {  // ta != tb here: i lies strictly between them
    const Vec3 q = s.colon.q.col(i);
    const double reach_m = m.colon.radius_m(i) + behind_m;  // the depth counts from here
    Vec3 y;
    double e2 = 0;
    int segment = -1;
    // Takes the nearest point of the chord x-z where it is nearer than the one held.
    auto consider = [&](const ChainNode& x, const ChainNode& z) {
      double w = 0;
      const Vec3 yz = nearestOnSegment(x.centre, z.centre, q, w);
      const double d2 = (yz - q).squaredNorm();
      if (segment >= 0 && !(d2 < e2)) return;
      y = yz;
      e2 = d2;
      segment = w < 0.5 ? x.segment : z.segment;
    };
    consider(a, b);
    // The neighbours can only bring the axis nearer: inside the reach of a-b (less the
    // margin), no contact.
    if (!(std::sqrt(e2) > reach_m - margin_m)) continue;
    if (before) consider(*before, a);
    if (after) consider(b, *after);
    const Vec3 d = y - q;
    const double e = std::sqrt(e2);
    const double depth = e - reach_m;
    if (!(depth > -margin_m)) continue;
    double weight = 1.0;
    if (first_chord) weight = std::min(weight, std::abs(i - ta) / kEndHandOver);
    if (last_chord) weight = std::min(weight, std::abs(tb - i) / kEndHandOver);
    WallContact c;
    c.scope_segment = segment;
    c.point = 0;
    c.p_W_point = y;
    c.colon_segment = i;
    c.p = 0.0;
    c.p_W_centre = q;
    c.normal_W = d / e;
    c.depth_m = depth;
    c.weight = weight;
    out.push_back(c);
  }
}

}  // namespace

void findThreadingContacts(const WorldModel& m, const WorldState& s, std::vector<WallContact>& out,
                           double margin_m) {
  const int slices = m.scope.params.slices_per_segment;
  // The chain of slices from the anus to the tip, as the tracking walks it; a slice
  // without a track breaks it. A window of four nodes: the chord between the middle two
  // is done when the node after it is known (or the chain ends), with its neighbours.
  ChainNode node[4];  // node[3] the newest
  int count = 0;      // nodes of the current chain so far
  auto endChain = [&]() {  // its last chord, node[2]-node[3]
    if (count >= 2) chordContacts(m, s, count >= 3 ? &node[1] : nullptr, node[2], node[3], nullptr, count == 2, true, margin_m,
                                  out);
    count = 0;
  };
  for (int k = s.scope.inside - 1; k >= 0; --k) {
    for (int sl = 0; sl < slices; ++sl) {
      const WallTrack& t = s.slice_track[static_cast<size_t>(k) * slices + sl];
      if (t.colon_segment < 0) {
        endChain();
        continue;
      }
      node[0] = node[1];
      node[1] = node[2];
      node[2] = node[3];
      node[3] = ChainNode{k, t.colon_segment + t.p, sliceCentre(m.scope, s.scope, k, sl)};
      ++count;
      if (count >= 3)  // the chord node[1]-node[2], with node[3] after it
        chordContacts(m, s, count >= 4 ? &node[0] : nullptr, node[1], node[2], &node[3], count == 3, false, margin_m,
                      out);
    }
  }
  endChain();
}

void applyThreadingContacts(const WorldModel& m, WorldState& s, double dt, const CouplingSweep* previous) {
  s.threading.clear();
  s.threading_near.clear();
  s.threading_stops.clear();
  const double k = m.contact.threading_stiffness_N_per_m;
  if (!(k > 0)) return;
  // The candidates: the control points one step at the scope's speed limit could take
  // beyond the wall's thickness.
  findThreadingContacts(m, s, s.threading_near, dt * m.scope.params.max_speed_m_per_s);
  const double held_m = m.contact.threading_stop_force_N / k;
  for (const WallContact& c : s.threading_near) {
    if (c.depth_m > 0) s.threading.push_back(c);
    if (!(c.weight > 0)) continue;
    WorldState::ThreadingStop stop;
    stop.scope_segment = c.scope_segment;
    stop.lever_W = c.p_W_point - s.scope.p_W[c.scope_segment];
    stop.point = c.colon_segment;
    stop.normal_W = c.normal_W;
    stop.depth_m = c.depth_m;
    stop.allowed_m = std::max(held_m / c.weight, c.depth_m);
    s.threading_stops.push_back(stop);
  }
  if (s.threading.empty()) return;
  // Eq. 7 with the threading stiffness from the depth beyond the wall's thickness: no
  // second backing.
  ContactParams p = m.contact;
  p.wall_stiffness_N_per_m = k;
  p.wall_backing_stiffness_N_per_m = 0;
  p.wall_reference_points_per_slice = 0;  // one contact per control point, whatever the points round a slice
  ContactLimitReport limit;
  // The coupling predictor leaves them out: held by 30,000 N/m on a 6 g control point and a
  // 3 g segment, the prediction would be scaled down to a few percent by its limit, and even so
  // it curled the bending section in extreme_all (docs/numerics.md, "The contacts' coupling").
  const double f = applyWallContacts(p, m.colon, s.colon, m.scope, s.scope, s.threading, s.colon.loads,
                                     s.scope.loads, &limit, 0.0, previous);
  s.max_wall_force_N = std::max(s.max_wall_force_N, f);
  limit.worst.kind = ContactLimitReport::Worst::Kind::kThreading;
  s.contact_limit.merge(limit);
}

void stopThreading(const WorldModel& /*model*/, WorldState& s, double dt) {
  ColonState& colon = s.colon;
  ScopeState& scope = s.scope;
  if (s.threading_stops.empty() || !colon.solver_ok || !scope.solver_ok) return;
  const int simulated = scope.simulated;
  double* xc = colon.scratch.data();
  double* xs = scope.guard_response.data();
  bool engaged = true;  // a second pass only after a first that engaged
  for (int pass = 0; pass < 2 && engaged; ++pass) {
    engaged = false;
    for (WorldState::ThreadingStop& st : s.threading_stops) {
      const int k = st.scope_segment, i = st.point;
      if (k >= simulated) continue;
      const Vec3& n = st.normal_W;
      // The depth at the end of the step, to first order: from the start's, at the rate the
      // two solved velocities give.
      const Vec3 v_y = scope.v_W[k] + scope.w_W[k].cross(st.lever_W);
      const double rate = (v_y - colon.v.col(i)).dot(n);
      const double excess_m = st.depth_m + dt * rate - st.allowed_m;
      if (!(excess_m > 1e-12)) continue;
      // Each body's velocity change along n per unit impulse, from its step's factors.
      colon.scratch.setZero();
      for (int c = 0; c < 3; ++c) xc[3 * i + c] = n(c);
      colon.system.solveInPlace(xc);
      const double r_colon = n.dot(Vec3(xc[3 * i], xc[3 * i + 1], xc[3 * i + 2]));
      const Vec3 ln = st.lever_W.cross(n);
      std::fill(xs, xs + 6 * simulated, 0.0);
      for (int c = 0; c < 3; ++c) xs[6 * k + c] = n(c), xs[6 * k + 3 + c] = ln(c);
      scope.system.solveInPlace(simulated, xs);
      const double r_scope = n.dot(Vec3(xs[6 * k], xs[6 * k + 1], xs[6 * k + 2])) +
                             ln.dot(Vec3(xs[6 * k + 3], xs[6 * k + 4], xs[6 * k + 5]));
      const double response = r_colon + r_scope;
      if (!(response > 0) || !std::isfinite(response)) continue;
      const double impulse = excess_m / (dt * response);
      // The colon pulled along +n, the scope pushed along -n: velocities, and the positions
      // they were integrated into.
      for (int j = 0; j < colon.q.cols(); ++j) {
        const Vec3 dv = impulse * Vec3(xc[3 * j], xc[3 * j + 1], xc[3 * j + 2]);
        colon.v.col(j) += dv;
        colon.q.col(j) += dt * dv;
      }
      for (int j = 0; j < simulated; ++j) {
        const Vec3 dv = -impulse * Vec3(xs[6 * j], xs[6 * j + 1], xs[6 * j + 2]);
        const Vec3 dw = -impulse * Vec3(xs[6 * j + 3], xs[6 * j + 4], xs[6 * j + 5]);
        scope.v_W[j] += dv;
        scope.w_W[j] += dw;
        scope.p_W[j] += dt * dv;
        scope.R_WS[j] = expSO3(dt * dw) * scope.R_WS[j];
        orthonormalize(scope.R_WS[j]);
      }
      st.impulse_Ns += impulse;
      engaged = true;
    }
  }
}

}  // namespace colosim
