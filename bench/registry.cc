#include "bench/registry.h"

namespace colosim {

const std::vector<BenchEntry>& benchmarks() {
  static const std::vector<BenchEntry> list = {
      {"colon", "colon step at 50, 100, 200, 400 control points (us per step)", benchColon},
      {"render", "onboard and global views at 640 x 480, adult colon, OSMesa (ms per frame)", benchRender},
  };
  return list;
}

}  // namespace colosim
