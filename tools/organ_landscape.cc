// The search landscape of one organ-level effect: how well the model replays a recording
// as the effect's magnitude varies (docs/organ-identification.md, "Landscape"):
//   organ_landscape FILE|hEFFECT:SEED SPACING_M EFFECT VALUE...
// replays the recording FILE (with its scenario and parameter file), for tEFFECT:SEED the
// organ trials' 2 s two-rate insertion (tools/organ_trials, made at the parameter file's
// resolution; DT=S in the environment makes it and replays it at that time step), or, for hEFFECT:SEED
// (e.g. hstrain_stiffening:201), the 3 s push-and-hold staircase of the hidden-effect test
// drawn as the test draws it (tests/identify/insertion/identify_test.cc), at the control-
// point spacing SPACING_M (0: the scenario's own), with EFFECT at each VALUE and nothing else
// on, and prints the RMS of the replay's handle force minus the recorded one about its mean,
// and that mean (the offset an identification fits) [N]. A landscape with steps or a
// narrow basin is one a grid-and-bracket search can miss. DUMP=1 also prints every row's
// recorded and replayed force.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "identify/insertion/replay.h"
#include "identify/insertion/synthetic.h"

int main(int argc, char** argv) {
  using namespace colosim;
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s FILE|tEFFECT:SEED|hEFFECT:SEED SPACING_M EFFECT VALUE...\n", argv[0]);
    return 2;
  }
  const std::string source = argv[1];
  const double spacing_m = std::atof(argv[2]);
  const std::string effect = argv[3];
  if (organEffectIndex(effect) < 0) {
    std::fprintf(stderr, "unknown effect '%s'\n", effect.c_str());
    return 2;
  }
  InsertionRecording rec;
  ReplaySetup setup;
  if (source.size() > 1 && (source[0] == 't' || source[0] == 'h') && source.find(':') != std::string::npos) {
    const std::string hidden = source.substr(1, source.find(':') - 1);
    const int index = organEffectIndex(hidden);
    if (index < 0 && hidden != "none") {
      std::fprintf(stderr, "unknown effect '%s'\n", hidden.c_str());
      return 2;
    }
    const uint64_t seed = std::strtoull(source.c_str() + source.find(':') + 1, nullptr, 10);
    SyntheticInsertionSpec spec;
    if (source[0] == 't') {
      ReplaySetup data = makeReplaySetup(findScenario("free_insertion_attached_rectum"));
      setup = makeReplaySetup(data.scenario, spacing_m);
      if (std::getenv("DT")) data.dt_s = setup.dt_s = std::atof(std::getenv("DT"));
      spec = drawTwoRateInsertion(seed, index, 2.0);
      rec = makeSyntheticInsertion(data, spec);
    } else {
      setup = makeReplaySetup(findScenario("free_insertion_attached_rectum"), spacing_m);
      spec = drawSyntheticInsertion(seed, index, 3.0, 0, 2);
      rec = makeSyntheticInsertion(setup, spec);
    }
    std::printf("drawn: hidden %s %.6g, seed %llu, %s\n", spec.effect.empty() ? "none" : spec.effect.c_str(), spec.value,
                static_cast<unsigned long long>(seed),
                source[0] == 't' ? "2 s two-rate insertion (organ_trials)" : "3 s staircase of 2 holds");
  } else {
    rec = readInsertionRecording(source);
    setup = makeReplaySetup(recordingScenario(rec), spacing_m);
  }
  for (int i = 4; i < argc; ++i) {
    OrganParams p;
    setOrganEffect(p, effect, std::atof(argv[i]));
    const Prediction pr = replayInsertion(setup, rec, p);
    const size_t n = pr.force_N.size();
    double mean = 0, ss = 0;
    for (size_t r = 0; r < n; ++r) mean += pr.force_N[r] - rec.force_N[r];
    mean /= static_cast<double>(n);
    for (size_t r = 0; r < n; ++r) ss += std::pow(pr.force_N[r] - rec.force_N[r] - mean, 2);
    std::printf("%s %-10.6g RMS %.4f N  offset %+.4f N%s\n", effect.c_str(), std::atof(argv[i]),
                std::sqrt(ss / static_cast<double>(n)), mean, pr.ok ? "" : "  (a solve failed)");
    std::fflush(stdout);
    if (std::getenv("DUMP")) {
      for (size_t r = 0; r < n; ++r)
        std::printf("  row %zu t %.3f ins %.4f data %.4f replay %.4f diff %+.4f\n", r, rec.time_s[r], rec.input[r].insertion_m,
                    rec.force_N[r], pr.force_N[r], pr.force_N[r] - rec.force_N[r] - mean);
    }
  }
  return 0;
}
