// Adds an endoscopist's steering to a scenario's script: the insertion and rotation stay
// as scripted, and from FROM_S on the knobs point the tip at the lumen ahead (the
// lumen-following controller's rule, trainer/lumen_following.h: the colon centreline
// LOOKAHEAD_M ahead of the tip, at most MAX_CHANGE_RAD of knob change per keyframe):
//   trainer_steer_script SCENARIO OUT.json [FROM_S]
// One keyframe every KEY_DT_S (default 0.5 s) and at each of the script's own keyframes
// (runWithLumenSteering), so the insertion and rotation keep their path. The simulation is
// stepped with the written script's interpolation, so OUT.json replays the same run
// (colosim run OUT.json --score). SCENARIO is a scenario file's path. Refuses to overwrite
// OUT.json.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
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
  WorldSimulation sim(sc);
  runWithLumenSteering(sc, sim, from_s, key_dt_s, lookahead_m, max_change_rad);
  const std::vector<Keyframe>& script = sc.script;
  std::printf("end %.1f s: hash %016llx\n", sim.time_s(), static_cast<unsigned long long>(sim.stateHash()));
  std::ifstream in(argv[1]);
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(in);
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const Keyframe& f : script) {
    nlohmann::json input;
    writeHandleInput(input, f.input);  // stiffness_level too, when the script sets it
    nlohmann::ordered_json k = {{"t_s", f.t_s}};
    for (const auto& [key, value] : input.items()) k[key] = value;
    for (const nlohmann::ordered_json& o : j["script"])  // the original keyframes' notes
      if (o.contains("note") && std::abs(o["t_s"].get<double>() - f.t_s) < 1e-9) k["note"] = o["note"];
    out.push_back(k);
  }
  j["script"] = out;
  std::ofstream(argv[2]) << j.dump(2) << "\n";
  return 0;
}
