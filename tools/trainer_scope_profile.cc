// Where the push goes (diagnosing a scripted insertion that stalls):
//   trainer_scope_profile SCENARIO T_S [T_S ...]
// runs the scenario as `colosim run` does and, at each time T_S [s], prints per colon region
// the scope length lying in it (segments by the nearest colon control point), the region's present and rest arclength (shortened: pleated
// onto the scope), the wall contact force on its scope segments and the scope's axial force
// where it enters the region (the joint penalty along the axis: negative in compression,
// positive in tension); then per scope segment, tip first, the same at segment resolution
// (SEGMENTS=1) with the joint's bend, the segment's centre and axis; CONTACTS=1 lists the
// wall contacts of the last 6 segments and the tracked colon segment of each interaction
// point of the last 10 (what collision/contact_query.cc tracks: docs/hardening.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/scope_step.h"
#include "core/spline.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

using namespace colosim;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SCENARIO T_S [T_S ...]\n", argv[0]);
    return 2;
  }
  const Scenario sc = findScenario(argv[1]);
  WorldSimulation sim(sc);
  const ScopeModel& sm = sim.model().scope;
  const ColonModel& cm = sim.model().colon;
  long k = 0;
  for (int a = 2; a < argc; ++a) {
    const long until = std::lround(std::atof(argv[a]) / sim.dt_s());
    for (; k < until; ++k) sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
    const WorldState& st = sim.state();
    const ScopeState& s = st.scope;
    // Each simulated segment's region: that of the colon control point nearest its centre.
    std::vector<int> region(s.inside, -1);
    std::vector<double> contact(s.inside, 0.0);
    for (int j = 0; j < s.inside; ++j) {
      int best = 0;
      for (int i = 1; i < cm.n; ++i)
        if ((st.colon.q.col(i) - s.p_W[j]).squaredNorm() < (st.colon.q.col(best) - s.p_W[j]).squaredNorm()) best = i;
      region[j] = cm.segment_region[std::min(best, cm.n - 2)];
    }
    for (const WallContact& c : st.wall)
      if (c.scope_segment < s.inside) contact[c.scope_segment] += c.force_N;
    auto axial = [&](int j) {  // joint j (segment j to j+1): - when the scope is compressed there, + in tension
      const double h = sm.h_m;
      const Vec3 gap = (s.p_W[j] - 0.5 * h * s.R_WS[j].col(2)) - (s.p_W[j + 1] + 0.5 * h * s.R_WS[j + 1].col(2));
      return sm.params.joint_stiffness_N_per_m * gap.dot(s.R_WS[j].col(2));
    };
    const Telemetry tel = sim.telemetry();
    std::printf("t %.3f s: insertion %.3f m, %d segments in, handle %.2f N, tip %.3f m along the colon, %.3f m from "
                "the caecal pole\n",
                sim.time_s(), s.input.insertion_m, s.inside, s.handle.force_N, tel.tip_arclength_m, tel.tip_to_caecum_m);
    std::printf("  %-16s %8s %8s %8s %9s %10s\n", "region", "scope_m", "colon_m", "rest_m", "contact_N",
                "axial_in_N");
    std::vector<double> colon_len(cm.region_names.size(), 0.0), rest_len(cm.region_names.size(), 0.0);
    for (int j = 0; j + 1 < cm.n; ++j) {
      colon_len[cm.segment_region[j]] += segmentArclength(st.colon.q, j);
      rest_len[cm.segment_region[j]] += cm.segment_length_m(j);
    }
    for (size_t r = 0; r < cm.region_names.size(); ++r) {
      double scope_len = 0, force = 0, axial_in = 0;
      int entry = -1;
      for (int j = 0; j < s.inside; ++j)
        if (region[j] == static_cast<int>(r)) scope_len += sm.h_m, force += contact[j], entry = std::max(entry, j);
      if (entry >= 0) axial_in = axial(entry);
      std::printf("  %-16s %8.3f %8.3f %8.3f %9.2f %10.2f\n", cm.region_names[r].c_str(), scope_len, colon_len[r],
                  rest_len[r], force, axial_in);
    }
    if (std::getenv("SEGMENTS"))
      for (int j = 0; j < s.inside; ++j)
        std::printf("    seg %3d %-16s contact %6.2f N axial %7.2f N bend %6.1f deg  p %.3f %.3f %.3f  z %.2f %.2f %.2f\n", j,
                    region[j] >= 0 ? cm.region_names[region[j]].c_str() : "-", contact[j], axial(j),
                    j + 1 < s.inside ? std::acos(std::clamp(s.R_WS[j].col(2).dot(s.R_WS[j + 1].col(2)), -1.0, 1.0)) *
                                           180.0 / 3.141592653589793
                                     : 0.0,
                    s.p_W[j].x(), s.p_W[j].y(), s.p_W[j].z(), s.R_WS[j].col(2).x(), s.R_WS[j].col(2).y(),
                    s.R_WS[j].col(2).z());
    if (std::getenv("CONTACTS")) {
      for (const WallContact& c : st.wall)
        if (c.scope_segment >= s.inside - 6)
          std::printf("    contact seg %d pt %d colon seg %d p %.3f depth %.4f N %.2f n %.2f %.2f %.2f axis.n %.2f\n",
                      c.scope_segment, c.point, c.colon_segment, c.p, c.depth_m, c.force_N, c.normal_W.x(),
                      c.normal_W.y(), c.normal_W.z(), c.normal_W.dot(s.R_WS[c.scope_segment].col(2)));
      const int P = static_cast<int>(sm.interaction_points_S.size());
      for (int j = std::max(0, s.inside - 10); j < s.inside; ++j) {
        std::printf("    tracks seg %d:", j);
        for (int i = 0; i < P; ++i) std::printf(" %d", st.track[static_cast<size_t>(j * P + i)].colon_segment);
        std::printf("\n");
      }
    }
  }
  return 0;
}
