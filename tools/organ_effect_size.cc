// How much an effect changes the handle force of a synthetic insertion protocol, noise-free
// (docs/organ-identification.md: whether an effect can be seen at all):
//   organ_effect_size EFFECT VALUE DURATION_S SEED [CYCLES|hHOLDS [AMPLITUDE_M START_M]]
// prints the RMS of the force difference between the replay with the effect and the paper's
// model, after removing its mean (a sensor offset absorbs that), and the white noise the
// recording of that seed would carry. Protocol and resolution as organ_make_insertion
// (hHOLDS, e.g. h2: the push-and-hold staircase of that many stages; AMPLITUDE_M its step).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "identify/insertion/synthetic.h"

int main(int argc, char** argv) {
  using namespace colosim;
  if (argc != 5 && argc != 6 && argc != 8) {
    std::fprintf(stderr, "usage: %s EFFECT VALUE DURATION_S SEED [CYCLES|hHOLDS [AMPLITUDE_M START_M]]\n", argv[0]);
    return 2;
  }
  const bool holds = argc > 5 && argv[5][0] == 'h';
  const int stages = argc > 5 ? std::atoi(argv[5] + (holds ? 1 : 0)) : 0;
  SyntheticInsertionSpec s = drawSyntheticInsertion(std::strtoull(argv[4], nullptr, 10), -1, std::atof(argv[3]),
                                                    holds ? 0 : stages, holds ? stages : 0);
  if (argc == 8) {
    (holds ? s.hold_step_m : s.cycle_amplitude_m) = std::atof(argv[6]);
    s.start_insertion_m = std::atof(argv[7]);
  }
  const ReplaySetup setup = makeReplaySetup(findScenario(s.scenario), 0.03);
  // The protocol's rows (a recording of the paper's model), replayed with and without the effect.
  const InsertionRecording rec = makeSyntheticInsertion(setup, s);
  OrganParams with;
  setOrganEffect(with, argv[1], std::atof(argv[2]));
  const Prediction a = replayInsertion(setup, rec, OrganParams{});
  const Prediction b = replayInsertion(setup, rec, with);
  const size_t n = rec.rows();
  double mean = 0;
  for (size_t k = 0; k < n; ++k) mean += (b.force_N[k] - a.force_N[k]) / n;
  double ss = 0, peak = 0, range_lo = 1e300, range_hi = -1e300;
  for (size_t k = 0; k < n; ++k) {
    const double d = b.force_N[k] - a.force_N[k] - mean;
    ss += d * d;
    peak = std::max(peak, std::abs(d));
    range_lo = std::min(range_lo, a.force_N[k]);
    range_hi = std::max(range_hi, a.force_N[k]);
  }
  std::printf("%s %g over %g s (seed %s, %s): force difference RMS %.4f N (peak %.3f N, mean %+.4f N); "
              "sensor noise %.4f N; paper's force spans %.2f .. %.2f N\n",
              argv[1], std::atof(argv[2]), s.duration_s, argv[4],
              s.cycles > 0  ? (std::to_string(s.cycles) + " cycles of " + std::to_string(s.cycle_amplitude_m) +
                               " m from " + std::to_string(s.start_insertion_m) + " m")
                                  .c_str()
              : s.holds > 0 ? (std::to_string(s.holds) + " push-and-hold stages of " + std::to_string(s.hold_step_m) +
                               " m from " + std::to_string(s.start_insertion_m) + " m")
                                  .c_str()
                            : "push-hold-pull-push",
              std::sqrt(ss / n), peak, mean, s.force_noise_N, range_lo, range_hi);
  return a.ok && b.ok ? 0 : 1;
}
