// Adds an endoscopist's steering to a scenario's script: the insertion and rotation stay
// as scripted, and from FROM_S on the knobs point the tip at the lumen ahead (the
// lumen-following controller's rule, trainer/lumen_following.h: the colon centreline
// LOOKAHEAD_M ahead of the tip, at most MAX_CHANGE_RAD of knob change per keyframe):
//   trainer_steer_script SCENARIO OUT.json [FROM_S]
// One keyframe every KEY_DT_S (default 0.5 s; the script's own keyframes must fall on this
// grid from FROM_S on, so that the insertion and rotation keep their path). The simulation
// is stepped with the written script's interpolation, so OUT.json replays the same run
// (colosim run OUT.json --score). SCENARIO is a scenario file's path. Refuses to overwrite
// OUT.json.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "trainer/lumen_following.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

using namespace colosim;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SCENARIO OUT.json [FROM_S]\n", argv[0]);
    return 2;
  }
  if (std::filesystem::exists(argv[2])) {
    std::fprintf(stderr, "%s: %s exists; not overwritten\n", argv[0], argv[2]);
    return 1;
  }
  auto setting = [](const char* name, double fallback) {
    const char* v = std::getenv(name);
    return v ? std::atof(v) : fallback;
  };
  const double lookahead_m = setting("LOOKAHEAD_M", 0.05);
  const double max_change_rad = setting("MAX_CHANGE_RAD", 0.4);
  const double key_dt_s = setting("KEY_DT_S", 0.5);
  Scenario sc = findScenario(argv[1]);
  const double from_s = argc > 3 ? std::atof(argv[3]) : 0.0;
  const std::vector<Keyframe> original = sc.script;
  for (const Keyframe& k : original) {
    const double n = (k.t_s - from_s) / key_dt_s;
    if (k.t_s > from_s && std::abs(n - std::round(n)) > 1e-9) {
      std::fprintf(stderr, "%s: keyframe at %.4f s is off the %.3f s grid from %.3f s\n", argv[0], k.t_s, key_dt_s,
                   from_s);
      return 1;
    }
  }
  // The script up to from_s, then keyframes on the grid.
  std::vector<Keyframe> script;
  for (const Keyframe& k : original)
    if (k.t_s < from_s) script.push_back(k);
  Keyframe first;
  first.t_s = from_s;
  first.input = scriptedInput(original, from_s);
  script.push_back(first);
  sc.script = script;
  WorldSimulation sim(sc);
  long k = 0;
  auto stepUntil = [&](double t_s) {
    for (const long until = std::lround(t_s / sim.dt_s()); k < until; ++k) {
      sim.step(scriptedInput(script, static_cast<double>(k) * sim.dt_s()));
    }
  };
  stepUntil(from_s);
  for (double t = from_s; t < sc.duration_s - 1e-9; t += key_dt_s) {
    Keyframe kf;
    kf.t_s = std::round((t + key_dt_s) * 1e4) / 1e4;
    const HandleInput planned = scriptedInput(original, kf.t_s);
    kf.input = steerTowardsLumen(sim, script.back().input, lookahead_m, max_change_rad);
    // The planned path, rounded (1e-6 m, 1e-6 rad) so that the file reads cleanly.
    kf.input.insertion_m = std::round(planned.insertion_m * 1e6) / 1e6;
    kf.input.rotation_rad = std::round(planned.rotation_rad * 1e6) / 1e6;
    script.push_back(kf);
    stepUntil(kf.t_s);
  }
  std::printf("end %.1f s: hash %016llx\n", sim.time_s(), static_cast<unsigned long long>(sim.stateHash()));
  std::ifstream in(argv[1]);
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(in);
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const Keyframe& f : script) {
    nlohmann::ordered_json k = {{"t_s", f.t_s}, {"insertion_m", f.input.insertion_m}, {"rotation_rad", f.input.rotation_rad},
                        {"knob_updown_rad", f.input.knob_updown_rad}, {"knob_leftright_rad", f.input.knob_leftright_rad}};
    for (const nlohmann::ordered_json& o : j["script"])  // the original keyframes' notes
      if (o.contains("note") && std::abs(o["t_s"].get<double>() - f.t_s) < 1e-9) k["note"] = o["note"];
    out.push_back(k);
  }
  j["script"] = out;
  std::ofstream(argv[2]) << j.dump(2) << "\n";
  return 0;
}
