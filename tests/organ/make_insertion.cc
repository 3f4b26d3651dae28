// Writes a synthetic insertion recording (organ/synthetic_insertion.h):
//   organ_make_insertion OUT.csv EFFECT VALUE DURATION_S SEED
// EFFECT "none" hides nothing. Made at the identification's search resolution (0.03 m).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "organ/synthetic_insertion.h"

int main(int argc, char** argv) {
  using namespace colosim;
  if (argc != 6) {
    std::fprintf(stderr, "usage: %s OUT.csv EFFECT|none VALUE DURATION_S SEED\n", argv[0]);
    return 2;
  }
  SyntheticInsertionSpec s = drawSyntheticInsertion(std::strtoull(argv[5], nullptr, 10), -1, std::atof(argv[4]));
  if (std::string(argv[2]) != "none") s.effect = argv[2], s.value = std::atof(argv[3]);
  const ReplaySetup setup = makeReplaySetup(findScenario(s.scenario), 0.03);
  const InsertionRecording r = makeSyntheticInsertion(setup, s);
  writeInsertionRecording(argv[1], r);
  return 0;
}
