// Writes a scripted insertion by driving the simulation with the lumen-following "expert"
// (trainer/lumen_following.h):
//   trainer_make_free_insertion TEMPLATE.json OUT.json [END_S]
// TEMPLATE is a scenario (anatomy, parameters, start, overrides, abdominal pressure; its
// script is replaced). Every 0.5 s the controller decides the next keyframe from the state:
// the knobs point the tip at the colon centreline LOOKAHEAD_M ahead of it (as an
// endoscopist steers towards the lumen; at most 0.4 rad of change per keyframe); the
// insertion advances at 2 cm/s. It withdraws at 2 cm/s, steering on (the hooked withdrawal
// that takes a loop out), when over the last WINDOW_S the tip gained less than a third of
// the scope pushed in and LOOP_M less in all (with more than 5 cm of slack), or when the
// scope is at the end of its working length with the tip still; it advances again after
// WITHDRAW_M came out or once the tip has come back BACK_M. It stops advancing once the
// tip is within 2.5 cm of the caecal pole. The simulation is stepped with the script's own
// interpolation (scriptedInput), so OUT.json replays the same run (colosim run OUT.json).
// The settings are environment variables (defaults: LOOKAHEAD_M 0.05, WINDOW_S 10,
// LOOP_M 0.15, WITHDRAW_M 0.3, BACK_M 0.02; PULL_MAX_N, off by default: the withdrawal
// pauses while the handle pulls harder, and after 2 s of pausing it advances again); VERBOSE=1 prints the state every 10 s.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "trainer/handle_io.h"
#include "trainer/lumen_following.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

using namespace colosim;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s TEMPLATE.json OUT.json [END_S]\n", argv[0]);
    return 2;
  }
  const double end_s = argc > 3 ? std::atof(argv[3]) : 180.0;
  Scenario sc = findScenario(argv[1]);
  sc.script.resize(1);
  sc.script[0].t_s = 0;
  sc.script[0].input = HandleInput();
  WorldSimulation sim(sc);
  auto knob = [](const char* name, double fallback) {
    const char* v = std::getenv(name);
    return v ? std::atof(v) : fallback;
  };
  LumenFollowingOptions o;
  o.lookahead_m = knob("LOOKAHEAD_M", o.lookahead_m);
  o.window_s = knob("WINDOW_S", o.window_s);
  o.loop_m = knob("LOOP_M", o.loop_m);
  o.withdraw_m = knob("WITHDRAW_M", o.withdraw_m);
  o.back_m = knob("BACK_M", o.back_m);
  o.pull_max_N = knob("PULL_MAX_N", o.pull_max_N);
  int withdrawals = 0;
  LumenFollowingHooks hooks;
  hooks.step_to_last_keyframe = true;  // the written script ends at its last keyframe
  hooks.log = [&](const std::string& line) {
    std::printf("%s\n", line.c_str());
    if (line.find(": withdraw (") != std::string::npos) ++withdrawals;
  };
  if (std::getenv("VERBOSE"))
    hooks.on_decision = [&](double t, const HandleInput& cur) {
      if (std::fmod(t, 10.0) >= 1e-9) return;
      const Telemetry tel = sim.telemetry();
      std::printf("t %.1f s: insertion %.3f m, tip %.3f m along the colon, %.3f m from the pole, handle %.1f N, knobs %.2f %.2f\n",
                  t, cur.insertion_m, tel.tip_arclength_m, tel.tip_to_caecum_m, sim.state().scope.handle.force_N,
                  cur.knob_updown_rad, cur.knob_leftright_rad);
    };
  runLumenFollowing(sc, sim, 0.0, end_s, o, hooks);
  const Telemetry tel = sim.telemetry();
  std::printf("end %.1f s: insertion %.3f m, tip %.3f m along the colon, %.3f m from the caecal pole, %d withdrawals, "
              "hash %016llx\n",
              sim.time_s(), sc.script.back().input.insertion_m, tel.tip_arclength_m, tel.tip_to_caecum_m, withdrawals,
              static_cast<unsigned long long>(sim.stateHash()));
  // The template with its script replaced.
  std::ifstream in(argv[1]);
  nlohmann::json j = nlohmann::json::parse(in);
  j["duration_s"] = sc.script.back().t_s;
  nlohmann::json script = nlohmann::json::array();
  for (const Keyframe& f : sc.script) {
    nlohmann::json k = {{"t_s", f.t_s}};
    writeHandleInput(k, f.input);  // stiffness_level too, when the controller sets it
    script.push_back(k);
  }
  j["script"] = script;
  std::ofstream(argv[2]) << j.dump(1) << "\n";
  return 0;
}
