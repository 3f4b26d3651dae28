// Step-by-step trace of a replay (diagnosing one-row handle-force spikes):
//   organ_force_probe RECORDING.csv|tEFFECT:SEED EFFECT|none VALUE FROM_S TO_S
// (tEFFECT:SEED: the organ trials' two-rate insertion of that seed, as organ_landscape;
// SPACING=M and DT=S in the environment replay at that spacing, default 0.03 m, and step)
// replays the recording as replayInsertion does (3 cm resolution; rest and settled starts, not
// a scenario's scripted set-up) and prints, for every
// 1 ms step in [FROM_S, TO_S], the insertion, the simulated segment count, the handle force,
// wall contacts on the last three simulated segments and the joint gaps at the anus.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/rotation.h"
#include "core/scope_step.h"
#include "identify/insertion/replay.h"
#include "identify/insertion/synthetic.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

using namespace colosim;

static double jointGap(const ScopeModel& m, const ScopeState& s, int k) {
  const double h = m.h_m;
  const Vec3 gap = (s.p_W[k] - 0.5 * h * s.R_WS[k].col(2)) - (s.p_W[k + 1] + 0.5 * h * s.R_WS[k + 1].col(2));
  return gap.norm();
}
static double jointAngle(const ScopeState& s, int k) {
  return logSO3(s.R_WS[k + 1].transpose() * s.R_WS[k]).norm();
}

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: %s RECORDING.csv|tEFFECT:SEED EFFECT|none VALUE FROM_S TO_S\n", argv[0]);
    return 2;
  }
  const std::string source = argv[1];
  const double spacing_m = std::getenv("SPACING") ? std::atof(std::getenv("SPACING")) : 0.03;
  InsertionRecording rec;
  ReplaySetup setup;
  if (source.size() > 1 && source[0] == 't' && source.find(':') != std::string::npos) {
    const ReplaySetup data = makeReplaySetup(findScenario("free_insertion_attached_rectum"));
    const std::string hidden = source.substr(1, source.find(':') - 1);
    const int index = organEffectIndex(hidden);
    if (index < 0 && hidden != "none") {
      std::fprintf(stderr, "unknown effect '%s'\n", hidden.c_str());
      return 2;
    }
    const SyntheticInsertionSpec spec =
        drawTwoRateInsertion(std::strtoull(source.c_str() + source.find(':') + 1, nullptr, 10), index, 2.0);
    rec = makeSyntheticInsertion(data, spec);
    setup = makeReplaySetup(data.scenario, spacing_m);
  } else {
    rec = readInsertionRecording(source);
    setup = makeReplaySetup(recordingScenario(rec), spacing_m);
  }
  OrganParams p;
  if (std::string(argv[2]) != "none") setOrganEffect(p, argv[2], std::atof(argv[3]));
  const double from = std::atof(argv[4]), to = std::atof(argv[5]);
  if (std::getenv("DT")) setup.dt_s = std::atof(std::getenv("DT"));
  WorldModel model = loadWorldModel(setup.scenario.anatomy_path, organParameters(setup.params, p));
  const double dt = setup.dt_s;
  StartSpec start = startSpecOf(setup.scenario);
  start.dt_s = dt;
  start.first_input = rec.input.front();
  WorldSimulation sim(std::move(model), start, "fcl");
  const WorldState& st = sim.state();
  const ScopeModel& sm = sim.model().scope;
  std::printf("step,t_s,insertion_m,inside,handle_N,asked_N,wall_contacts,wall_last3_N,wall_max_N,"
              "gap_last_um,gap_prev_um,angle_last_rad,angle_prev_rad,v_last_axial,limited\n");
  const long n = std::lround(rec.time_s.back() / dt);
  for (long step = 1; step <= n; ++step) {
    const int inside_before = st.scope.inside;
    sim.step(recordedInput(rec, step * dt));
    const double t = step * dt;
    if (t < from - 1e-9 || t > to + 1e-9) continue;
    const ScopeState& s = st.scope;
    double last3 = 0;
    int nc = 0;
    for (const WallContact& c : st.wall) {
      ++nc;
      if (c.scope_segment >= s.inside - 3) last3 += c.force_N;
    }
    const int j = s.inside - 1;
    std::printf("%ld,%.3f,%.6f,%d%s,%.4f,%.4f,%d,%.4f,%.4f,%.3f,%.3f,%.5f,%.5f,%.5f,%d\n", step, t, s.input.insertion_m,
                s.inside, s.inside != inside_before ? "*" : "", s.handle.force_N, s.asked_handle_force_N, nc, last3,
                st.max_wall_force_N, j >= 0 ? 1e6 * jointGap(sm, s, j) : 0.0,
                j >= 1 ? 1e6 * jointGap(sm, s, j - 1) : 0.0, j >= 0 ? jointAngle(s, j) : 0.0,
                j >= 1 ? jointAngle(s, j - 1) : 0.0, j >= 0 ? s.v_W[j].dot(sm.R_W_entry.col(2)) : 0.0,
                limitedCount(st));
  }
  return 0;
}
