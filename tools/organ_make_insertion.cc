// Writes a synthetic insertion recording (identify/insertion/synthetic.h):
//   organ_make_insertion OUT.csv EFFECT VALUE DURATION_S SEED [CYCLES|hHOLDS [AMPLITUDE_M START_M]]
// EFFECT "none" hides nothing; VALUE "drawn" draws it (and the protocol) as the tests do. CYCLES > 0: insert / withdraw cycles (amplitude and start depth
// drawn from the seed unless given); hHOLDS (e.g. h2): that many push-and-hold stages (AMPLITUDE_M: the step). Made at the parameter file's resolution (0.015 m),
// twice as fine as the identification's search (0.03 m): data the search's model did not make.
// DT=S makes it with that time step [s] instead of the replays' 1 ms (0.00025: a step the
// replays do not take, closer to the time-converged motion, as a recording of the world is).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "identify/insertion/synthetic.h"

int main(int argc, char** argv) {
  using namespace colosim;
  if (argc != 6 && argc != 7 && argc != 9) {
    std::fprintf(stderr, "usage: %s OUT.csv EFFECT|none VALUE|drawn DURATION_S SEED [CYCLES|hHOLDS [AMPLITUDE_M START_M]]\n",
                 argv[0]);
    return 2;
  }
  // VALUE "drawn": the magnitude (and the protocol) drawn as the tests draw them for EFFECT.
  const std::string effect = argv[2], value = argv[3];
  const int index = value == "drawn" ? organEffectIndex(effect) : -1;
  const bool holds = argc > 6 && argv[6][0] == 'h';
  const int stages = argc > 6 ? std::atoi(argv[6] + (holds ? 1 : 0)) : 0;
  SyntheticInsertionSpec s = drawSyntheticInsertion(std::strtoull(argv[5], nullptr, 10), index, std::atof(argv[4]),
                                                    holds ? 0 : stages, holds ? stages : 0);
  if (argc == 9) {
    (holds ? s.hold_step_m : s.cycle_amplitude_m) = std::atof(argv[7]);
    s.start_insertion_m = std::atof(argv[8]);
  }
  if (effect != "none" && value != "drawn") s.effect = effect, s.value = std::atof(argv[3]);
  ReplaySetup setup = makeReplaySetup(findScenario(s.scenario));
  if (const char* dt = std::getenv("DT")) {
    setup.dt_s = std::atof(dt);
    if (!(setup.dt_s >= 1e-5 && setup.dt_s <= 1e-2)) {
      std::fprintf(stderr, "DT must be within [1e-5, 1e-2] s\n");
      return 2;
    }
  }
  const InsertionRecording r = makeSyntheticInsertion(setup, s);
  writeInsertionRecording(argv[1], r);
  return 0;
}
