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
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "core/lumen_check.h"
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
  for (long k = 0; k < steps && (fresh || reports < max_reports); ++k) {
    sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
    const WorldState& s = sim.state();
    const LumenCheck c = checkLumen(m, s, arc);
    if (fresh) {
      WorldState again = s;
      query->findWallContacts(m, again);
      const LumenCheck f = checkLumen(m, again, arc);
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
        const double d = (x - splinePoint(s.colon.q, t.colon_segment, t.p)).norm();
        const ClosestPoint near = closestPointOnSpline(s.colon.q, x);
        const bool out = d > m.colon.radiusAt(t.colon_segment, t.p);
        const double a_m = at[t.colon_segment] + t.p * (at[t.colon_segment + 1] - at[t.colon_segment]);
        const double jump_m = previous_m < 0 ? 0.0 : std::abs(a_m - previous_m) - m.scope.h_m / slices;
        previous_m = a_m;
        if (!all && !out && jump_m < 0.03 && std::abs(near.segment - t.colon_segment) <= 1) continue;
        if (jump_m >= 0.03) std::printf("  (jump %.4f m)\n", jump_m);
        std::printf("  segment %3d slice %d  x (%7.3f %7.3f %7.3f)  track %3d/%.2f  d %.4f r %.4f  %s| nearest %3d/%.2f d %.4f\n",
                    seg, sl, x.x(), x.y(), x.z(), t.colon_segment, t.p, d, m.colon.radiusAt(t.colon_segment, t.p),
                    d > m.colon.radiusAt(t.colon_segment, t.p) ? "OUT " : "    ", near.segment, near.p, near.distance);
      }
  }
  if (fresh)
    for (int i = 0; i < 2; ++i)
      std::printf("%s: lumen exit steps %ld, largest jump %.4f m, deepest point %.4f m\n",
                  i == 0 ? "run's measure (start tracks)" : "fresh tracks (end state)  ", exits[i],
                  worst[i].track_jump_m, worst[i].wall_penetration_m);
  return 0;
}
