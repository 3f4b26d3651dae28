#include "bench/registry.h"

namespace colosim {

const std::vector<BenchEntry>& benchmarks() {
  static const std::vector<BenchEntry> list = {
      {"colon", "colon step at 50, 100, 200, 400 control points (us per step)", benchColon},
  };
  return list;
}

}  // namespace colosim
