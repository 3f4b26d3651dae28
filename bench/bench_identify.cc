// colosim bench identify: the whole identification of a 10,000-row tension test (the
// target is under 2 s on this machine). The file is made by the seeded generator with a
// hidden effect, written and read back, so the reader is timed too.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <unistd.h>
#include <vector>

#include "bench/registry.h"
#include "identify/tension/identify.h"
#include "identify/tension/synthetic.h"

namespace colosim {

BenchOutput benchIdentify() {
  SyntheticDraw draw;
  draw.effects = {"strain_stiffening", "stress_relaxation"};  // two rounds of selection
  draw.cycles = 11;
  // Choose the sampling interval that gives 10,000 rows for this protocol.
  SyntheticSpec spec = drawSyntheticSpec(20261122, draw);
  spec.nominal_dt_s = (protocolDuration(spec) + 3.0) / 10100.0;
  TensionTest test = generateTensionTest(spec);
  test.time_s.resize(std::min<size_t>(test.rows(), 10000));
  test.elongation_m.resize(test.time_s.size());
  test.force_N.resize(test.time_s.size());
  const std::string path =
      (std::filesystem::temp_directory_path() / ("colosim-bench-identify-" + std::to_string(::getpid()) + ".csv")).string();
  writeTensionTest(path, test);

  constexpr int kRuns = 5;
  std::vector<double> seconds;
  IdentifyResult r;
  size_t rows = 0;
  for (int k = 0; k < kRuns; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const TensionTest t = readTensionTest(path);
    r = identifyTension(t);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    rows = t.rows();
  }
  std::filesystem::remove(path);
  std::vector<double> sorted = seconds;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[kRuns / 2];
  std::string effects;
  for (const std::string& e : r.effects) effects += (effects.empty() ? "" : ", ") + e;
  char text[512];
  std::snprintf(text, sizeof text,
                "identify: read + identify a %zu-row tension test (hidden: strain_stiffening + stress_relaxation)\n"
                "  median of %d runs: %.3f s (min %.3f, max %.3f); target < 2 s\n"
                "  found: [%s], held-out RMSE ratio %.2f\n",
                rows, kRuns, median, sorted.front(), sorted.back(), effects.c_str(), r.heldout_rmse_ratio);
  BenchOutput out;
  out.json = {{"benchmark", "identify"}, {"rows", rows},         {"runs", kRuns},
              {"seconds", seconds},      {"median_s", median},   {"target_s", 2.0},
              {"effects", r.effects},    {"heldout_rmse_ratio", r.heldout_rmse_ratio}};
  out.text = text;
  return out;
}

}  // namespace colosim
