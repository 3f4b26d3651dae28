// Where the contact topology fails (core/lumen_check.h):
//   trainer_lumen_probe SCENARIO [MAX_REPORTS]
// runs the scenario as `colosim run` does and, at each step whose contact-topology check
// fails (a lumen exit, a track jump of 0.03 m or more, or a penetration of 5 mm or more),
// up to MAX_REPORTS (default 3) of them, prints per slice of the scope, anus first: its
// centre, its tracked colon segment and parameter, the distance to the tracked centreline
// point against the lumen radius there, and where the paper's nearest point would be: the
// slices out of their lumen or tracked off the nearest point, every slice with ALL_SLICES=1.
// FRESH=1 runs the whole scenario and ends with the run's measure (the step's start tracks
// against its end positions, as `colosim run` counts) next to the same measure on fresh
// tracks (the end state copied and its contacts found again, as the next step will): where
// the scope slides along a taper, the first can count a slice that a fresh track finds inside.
// With FRESH=1 each reported slice out of its lumen also shows its fresh track, and the end
// counts the exit steps whose every slice out is inside on a fresh track (the run's measure
// only: the slice crossed into the next tube of the same colon within the step).
// Each report gives the handle's force and torque and the contacts' normal forces (summed
// and largest: the wall's interaction points, the threading contacts), so that a wedge or a
// coil pressed out by torque shows itself. LIMITS=1 prints every solver_limited event as
// it happens (what was limited, asked against the limit: docs/hardening.md). BENDS=DEG prints,
// at every step, each joint inside bent by more than DEG degrees (the bending section curled
// on itself, a kink where the shaft's ring leaves a joint's outer corner unsampled).
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "core/lumen_check.h"
#include "core/rotation.h"
#include "core/spline.h"
#include "collision/contact_query.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

using namespace colosim;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENARIO [MAX_REPORTS]\n", argv[0]);
    return 2;
  }
  const Scenario sc = findScenario(argv[1]);
  const int max_reports = argc > 2 ? std::atoi(argv[2]) : 3;
  WorldSimulation sim(sc);
  const WorldModel& m = sim.model();
  std::vector<double> arc;
  int reports = 0;
  const long steps = std::lround(sc.duration_s / sim.dt_s());
  const bool fresh = std::getenv("FRESH") != nullptr;
  std::unique_ptr<ContactQuery> query = fresh ? makeContactQuery(m, "fcl") : nullptr;
  LumenCheck worst[2];  // the run's measure, on fresh tracks
  long exits[2] = {0, 0};
  long run_only_exits = 0;  // exit steps of the run's measure with every slice out inside on a fresh track
  const bool limits = std::getenv("LIMITS") != nullptr;
  // A slice's centre against the lumen of a track: distance [m] and whether it is outside.
  auto against = [&](const WorldState& st, const WallTrack& t, const Vec3& x, double* d) {
    *d = (x - splinePoint(st.colon.q, t.colon_segment, t.p)).norm();
    return *d > m.colon.radiusAt(t.colon_segment, t.p);
  };
  for (long k = 0; k < steps && (fresh || reports < max_reports); ++k) {
    sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
    const WorldState& s = sim.state();
    const LumenCheck c = checkLumen(m, s, arc);
    if (std::getenv("BENDS")) {  // BENDS=DEG: every joint inside bent beyond DEG degrees
      const double limit_rad = std::atof(std::getenv("BENDS")) * M_PI / 180;
      for (int j = 0; j + 1 < s.scope.inside; ++j) {
        const Vec3 w = logSO3(s.scope.R_WS[j + 1].transpose() * s.scope.R_WS[j]);
        const double bend = std::hypot(w.x(), w.y());
        if (bend > limit_rad)
          std::printf("t %.3f s: joint %d bent %.1f deg (torsion %.1f deg)\n", sim.time_s(), j, bend * 180 / M_PI,
                      w.z() * 180 / M_PI);
      }
    }
    if (limits)
      for (const SimulationEvent& e : sim.events())
        if (e.name == "solver_limited") std::printf("t %.3f s: solver_limited: %s\n", sim.time_s(), e.detail.c_str());
    WorldState again;  // with FRESH, the end state with its contacts found again
    if (fresh) {
      again = s;
      query->findWallContacts(m, again);
      const LumenCheck f = checkLumen(m, again, arc);
      if (c.lumen_exit) {  // every slice out of its start track's lumen inside on its fresh track?
        bool all_inside = true;
        const int slices = m.scope.params.slices_per_segment;
        for (int seg = 0; seg < s.scope.inside && all_inside; ++seg)
          for (int sl = 0; sl < slices; ++sl) {
            const WallTrack& t0 = s.slice_track[seg * slices + sl];
            const WallTrack& t1 = again.slice_track[seg * slices + sl];
            if (t0.colon_segment < 0 || t1.colon_segment < 0) continue;
            const Vec3 x = sliceCentre(m.scope, s.scope, seg, sl);
            double d0, d1;
            if (against(s, t0, x, &d0) && against(again, t1, x, &d1)) all_inside = false;
          }
        if (all_inside) ++run_only_exits;
      }
      int i = 0;
      for (const LumenCheck* x : {&c, &f}) {
        exits[i] += x->lumen_exit ? 1 : 0;
        worst[i].track_jump_m = std::max(worst[i].track_jump_m, x->track_jump_m);
        worst[i].wall_penetration_m = std::max(worst[i].wall_penetration_m, x->wall_penetration_m);
        ++i;
      }
    }
    if (reports >= max_reports) continue;
    if (!c.lumen_exit && c.track_jump_m < 0.03 && c.wall_penetration_m < 0.005) continue;
    if (std::getenv("FROM_S") && sim.time_s() < std::atof(std::getenv("FROM_S"))) continue;  // reports from this time [s]
    const bool all = std::getenv("ALL_SLICES") != nullptr;
    ++reports;
    std::printf("t %.3f s: jump %.4f m, penetration %.4f m, exit %d, insertion %.3f m, %d segments in\n", sim.time_s(),
                c.track_jump_m, c.wall_penetration_m, c.lumen_exit ? 1 : 0, s.scope.input.insertion_m, s.scope.inside);
    {
      double wall_sum = 0, wall_max = 0, thread_sum = 0, thread_max = 0;
      for (const WallContact& w : s.wall) wall_sum += w.normal_force_N, wall_max = std::max(wall_max, w.normal_force_N);
      for (const WallContact& w : s.threading)
        thread_sum += w.normal_force_N, thread_max = std::max(thread_max, w.normal_force_N);
      std::printf("  handle %.1f N, %.3f N m; wall: %zu points, %.1f N in all, largest %.1f N; threading: %zu, %.1f N, "
                  "largest %.1f N; contacts limited %d\n",
                  s.scope.handle.force_N, s.scope.handle.torque_Nm, s.wall.size(), wall_sum, wall_max, s.threading.size(),
                  thread_sum, thread_max, s.contact_limit.limited);
    }
    const int slices = m.scope.params.slices_per_segment;
    // Present arclength at the control points, as checkLumen measures it [m].
    std::vector<double> at(m.colon.n, 0.0);
    for (int j = 0; j + 1 < m.colon.n; ++j) at[j + 1] = at[j] + (s.colon.q.col(j + 1) - s.colon.q.col(j)).norm();
    double previous_m = -1;
    if (std::getenv("COLON_POINTS"))  // the control points COLON_POINTS=A-B: present place, rest place
      for (int i = std::atoi(std::getenv("COLON_POINTS")); i <= std::atoi(std::strchr(std::getenv("COLON_POINTS"), '-') + 1); ++i)
        std::printf("  colon %3d (%7.3f %7.3f %7.3f) rest (%7.3f %7.3f %7.3f) arclength %.4f m (rest %.4f)\n", i,
                    s.colon.q(0, i), s.colon.q(1, i), s.colon.q(2, i), m.colon.q_rest(0, i), m.colon.q_rest(1, i),
                    m.colon.q_rest(2, i), at[i], m.colon.s_rest_m(i));
    for (int seg = s.scope.inside - 1; seg >= 0; --seg)
      for (int sl = 0; sl < slices; ++sl) {
        const WallTrack& t = s.slice_track[seg * slices + sl];
        const Vec3 x = sliceCentre(m.scope, s.scope, seg, sl);
        if (t.colon_segment < 0) continue;
        double d;
        const bool out = against(s, t, x, &d);
        const ClosestPoint near = closestPointOnSpline(s.colon.q, x);
        const double a_m = at[t.colon_segment] + t.p * (at[t.colon_segment + 1] - at[t.colon_segment]);
        const double jump_m = previous_m < 0 ? 0.0 : std::abs(a_m - previous_m) - m.scope.h_m / slices;
        previous_m = a_m;
        if (!all && !out && jump_m < 0.03 && std::abs(near.segment - t.colon_segment) <= 1) continue;
        if (jump_m >= 0.03) std::printf("  (jump %.4f m)\n", jump_m);
        std::printf("  segment %3d slice %d  x (%7.3f %7.3f %7.3f)  track %3d/%.2f  d %.4f r %.4f  %s| nearest %3d/%.2f d %.4f",
                    seg, sl, x.x(), x.y(), x.z(), t.colon_segment, t.p, d, m.colon.radiusAt(t.colon_segment, t.p),
                    out ? "OUT " : "    ", near.segment, near.p, near.distance);
        if (fresh && out) {
          const WallTrack& t1 = again.slice_track[seg * slices + sl];
          double d1 = 0;
          const bool out1 = t1.colon_segment >= 0 && against(again, t1, x, &d1);
          std::printf(" | fresh %3d/%.2f d %.4f %s", t1.colon_segment, t1.p, d1, out1 ? "OUT" : "inside");
        }
        std::printf("\n");
      }
  }
  if (fresh)
    for (int i = 0; i < 2; ++i)
      std::printf("%s: lumen exit steps %ld, largest jump %.4f m, deepest point %.4f m\n",
                  i == 0 ? "run's measure (start tracks)" : "fresh tracks (end state)  ", exits[i],
                  worst[i].track_jump_m, worst[i].wall_penetration_m);
  if (fresh)
    std::printf("exit steps of the run's measure whose slices out are all inside on fresh tracks: %ld\n", run_only_exits);
  return 0;
}
