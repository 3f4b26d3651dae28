// One case of the hidden-effect test (tests/identify/insertion/identify_test.cc) for any seed:
//   organ_hidden_identify EFFECT|none DURATION_S SEED [CYCLES|hHOLDS]
// draws the recording as the test draws it (magnitude, protocol and noise from the seed;
// hHOLDS, e.g. h2: the push-and-hold staircase of that many stages), identifies it and
// prints the hidden effect, what was named, the held-out gain, the CPU time and the diagnosis.
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

#include "identify/insertion/identify.h"
#include "identify/insertion/synthetic.h"

int main(int argc, char** argv) {
  using namespace colosim;
  if (argc != 4 && argc != 5) {
    std::fprintf(stderr, "usage: %s EFFECT|none DURATION_S SEED [CYCLES|hHOLDS]\n", argv[0]);
    return 2;
  }
  const std::string effect = argv[1];
  const int index = organEffectIndex(effect);
  if (index < 0 && effect != "none") {
    std::fprintf(stderr, "unknown effect '%s'\n", argv[1]);
    return 2;
  }
  const bool holds = argc > 4 && argv[4][0] == 'h';
  const int stages = argc > 4 ? std::atoi(argv[4] + (holds ? 1 : 0)) : 0;
  const SyntheticInsertionSpec spec = drawSyntheticInsertion(std::strtoull(argv[3], nullptr, 10), index,
                                                             std::atof(argv[2]), holds ? 0 : stages, holds ? stages : 0);
  const ReplaySetup setup = makeReplaySetup(findScenario(spec.scenario), 0.03);
  const std::clock_t c0 = std::clock();
  const InsertionRecording rec = makeSyntheticInsertion(setup, spec);
  const InsertionIdentifyResult r = identifyInsertion(rec, setup);
  const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  std::string found;
  for (const std::string& e : r.effects) found += (found.empty() ? "" : " + ") + e;
  std::string protocol = "push-hold-pull-push";
  for (const auto& kv : rec.metadata)
    if (kv.first == "protocol") protocol = kv.second;
  std::printf("seed %s: hidden %s %.4g (%s; noise %.3f N): found [%s]", argv[3], index < 0 ? "none" : effect.c_str(),
              spec.value, protocol.c_str(), spec.force_noise_N, found.c_str());
  if (!r.effects.empty()) std::printf(" %.4g", organEffectValue(r.extended.params, r.effects.front()));
  std::printf(", held-out gain %.3f, %s%d simulations, %.1f s wall, %.1f s CPU\n", r.heldout_rmse_ratio,
              r.unexplained ? "unexplained, " : "", r.simulations, r.seconds, cpu);
  for (const CandidateEvidence& e : r.evidence)
    std::printf("  round %d %-22s value %-9.4g held-out ratio %.3f dBIC %+.1f%s%s\n", e.round, e.effect.c_str(), e.value,
                e.heldout_ratio, e.delta_bic, e.pays ? " pays" : "", e.chosen ? " CHOSEN" : "");
  std::printf("%s", r.diagnosis.c_str());
  return 0;
}
