#include "bench/registry.h"

namespace colosim {

const std::vector<BenchEntry>& benchmarks() {
  static const std::vector<BenchEntry> list = {
      {"colon", "colon step at 50, 100, 200, 400 control points (us per step)", [](const BenchOptions&) { return benchColon(); }},
      {"contacts", "contact queries, FCL against the paper's scan, and the whole step (scope at the caecum)",
       [](const BenchOptions&) { return benchContacts(); }},
      {"untwist", "sigmoid_untwist headless: real-time factor, also recording and replaying", [](const BenchOptions&) { return benchUntwist(); }},
      {"identify", "identification of a 10,000-row tension test (median seconds of 5 runs)", [](const BenchOptions&) { return benchIdentify(); }},
      {"render", "onboard and global views at 640 x 480, adult colon, OSMesa (ms per frame)", [](const BenchOptions&) { return benchRender(); }},
      {"endurance",
       "--hours H (default 1) of cyclic scripted use on the colon + scope simulation: energy over time, "
       "memory (VmRSS, VmHWM), steps per second",
       benchEndurance, true},
      {"peer",
       "the scope in colosim against the same scope in MuJoCo (colon rigid in both), 10 s of scripted "
       "insertion and rotation at 1 ms: step times, their ratio, tip and handle-force differences "
       "(exit 2 in a build without MuJoCo)",
       [](const BenchOptions&) { return benchPeerDefault(); }},
  };
  return list;
}

}  // namespace colosim
