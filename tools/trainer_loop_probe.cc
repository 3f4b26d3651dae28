// How a loop behaves under a scripted manoeuvre (issue 21: loops that need torque):
//   trainer_loop_probe SCENARIO [EVERY_S]
// runs the scenario as `colosim run` does and prints, every EVERY_S [s] (default 0.5), the
// handle's insertion [m] and rotation [rad], the coronal crossing loop measure and the 3-D
// writhe [turns], the handle torque [N m] and force [N], the grip's rotation slip [rad], the
// tip's rest arclength [m], the sigmoid's present/rest length, and the twist stored in the
// inside scope [rad] (the sum of the joints' torsion angles) and how far the tip has spun
// about its own axis [rad] (its spin integrated over time). Then one summary line: the
// first time after the scored start when |writhe| stays below 0.5 turn to the end ("loop
// gone at"), the largest |torque| and the final writhe; and how far the tip slid back along
// the colon from the scored start to the end (rest arclength, positive back) and the largest
// pull, which together tell a hooked tip that held from one that let go (session 30).
// Variants without editing files:
//   PARAMS=FILE          use this parameter file (as colosim run --params)
//   ROTATION_SCALE=F     multiply every keyframe's rotation by F (0: no rotation, -1: the other way)
//   KNOB_UP_RAD=A        add A [rad] to every keyframe's up/down knob (a tip hooked from the start)
//   DURATION_S=T         stop after T [s] of simulated time
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/rotation.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

using namespace colosim;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENARIO [EVERY_S]\n", argv[0]);
    return 2;
  }
  Scenario sc = findScenario(argv[1]);
  const double every_s = argc > 2 ? std::atof(argv[2]) : 0.5;
  if (const char* p = std::getenv("PARAMS")) useParameterFile(sc, p);
  if (const char* f = std::getenv("ROTATION_SCALE"))
    for (Keyframe& k : sc.script) k.input.rotation_rad *= std::atof(f);
  if (const char* a = std::getenv("KNOB_UP_RAD"))
    for (Keyframe& k : sc.script) k.input.knob_updown_rad += std::atof(a);
  if (const char* d = std::getenv("DURATION_S")) sc.duration_s = std::min(sc.duration_s, std::atof(d));
  WorldSimulation sim(sc);
  const ColonModel& cm = sim.model().colon;
  int sigmoid = -1;
  for (size_t r = 0; r < cm.region_names.size(); ++r)
    if (cm.region_names[r] == "sigmoid") sigmoid = static_cast<int>(r);
  const long steps = sc.steps();
  const long every = std::max(1L, std::lround(every_s / sim.dt_s()));
  double peak_torque = 0, gone_at = -1;
  double tip_at_start_m = -1, largest_pull_N = 0;
  std::printf("%7s %7s %7s %6s %7s %8s %7s %7s %7s %7s %7s %7s\n", "t_s", "ins_m", "rot_rad", "cross", "writhe",
              "torq_Nm", "force_N", "slip_rd", "tip_m", "sigm", "twist", "tipspin");
  double tip_spin_rad = 0;  // integral of the tip segment's spin about its own axis
  for (long k = 0; k < steps; ++k) {
    sim.step(scriptedInput(sc.script, static_cast<double>(k) * sim.dt_s()));
    tip_spin_rad += sim.state().scope.w_W[0].dot(sim.state().scope.R_WS[0].col(2)) * sim.dt_s();
    const Telemetry t = sim.telemetry();
    if (t.time_s > sc.scoring.start_s) {
      if (tip_at_start_m < 0) tip_at_start_m = t.tip_arclength_m;
      largest_pull_N = std::max(largest_pull_N, -t.handle_force_N);
      peak_torque = std::max(peak_torque, std::abs(t.handle_torque_Nm));
      if (std::abs(t.loop_writhe) >= 0.5) gone_at = -1;
      else if (gone_at < 0) gone_at = t.time_s;
    }
    if ((k + 1) % every != 0) continue;
    const ScopeState& s = sim.state().scope;
    double twist_rad = 0;
    for (int j = 0; j + 1 < s.inside; ++j)
      twist_rad += logSO3(s.R_WS[j + 1].transpose() * s.R_WS[j]).z();
    std::printf("%7.2f %7.3f %7.2f %6.1f %7.3f %8.4f %7.2f %7.3f %7.3f %7.3f %7.3f %7.2f\n", t.time_s, t.input.insertion_m,
                t.input.rotation_rad, t.loop_turns, t.loop_writhe, t.handle_torque_Nm, t.handle_force_N,
                s.grip_slip_rad, t.tip_arclength_m, sigmoid >= 0 ? t.region_length_ratio[sigmoid] : 0.0, twist_rad, tip_spin_rad);
  }
  const Telemetry t = sim.telemetry();
  std::printf("loop gone at %s s, peak |torque| %.4f N m, final writhe %.3f, final crossing %.1f, "
              "tip back %.3f m, largest pull %.1f N\n",
              gone_at < 0 ? "never" : std::to_string(gone_at).c_str(), peak_torque, t.loop_writhe, t.loop_turns,
              tip_at_start_m < 0 ? 0.0 : tip_at_start_m - t.tip_arclength_m, largest_pull_N);
  return 0;
}
