#include "bench/registry.h"

namespace colosim {

const std::vector<BenchEntry>& benchmarks() {
  static const std::vector<BenchEntry> list = {
      {"colon", "colon step at 50, 100, 200, 400 control points (us per step)", benchColon},
      {"contacts", "contact queries, FCL against the paper's scan, and the whole step (scope at the caecum)",
       benchContacts},
      {"untwist", "sigmoid_untwist headless: real-time factor, also recording and replaying", benchUntwist},
      {"identify", "identification of a 10,000-row tension test (median seconds of 5 runs)", benchIdentify},
      {"render", "onboard and global views at 640 x 480, adult colon, OSMesa (ms per frame)", benchRender},
  };
  return list;
}

}  // namespace colosim
