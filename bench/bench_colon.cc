// colosim bench colon: the colon step's cost against the number of control points.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "bench/registry.h"
#include "core/colon_step.h"
#include "trainer/assets.h"

namespace colosim {

namespace {

// Median microseconds per step over `blocks` blocks of `block_steps` steps, after a warm-up.
double medianStepMicros(const ColonModel& model, double dt, int blocks, int block_steps) {
  ColonState state = makeColonState(model);
  for (int k = 0; k < block_steps; ++k) stepColon(model, state, dt);
  std::vector<double> us;
  for (int b = 0; b < blocks; ++b) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < block_steps; ++k) stepColon(model, state, dt);
    const auto t1 = std::chrono::steady_clock::now();
    us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / block_steps);
  }
  std::nth_element(us.begin(), us.begin() + us.size() / 2, us.end());
  return us[us.size() / 2];
}

}  // namespace

BenchOutput benchColon() {
  const Parameters params = loadParameters(assetPath("params/default.json"));
  const Anatomy anatomy = loadAnatomy(assetPath("anatomy/adult.json"));
  const std::vector<int> sizes = {50, 100, 200, 400};
  std::vector<double> us;
  std::string text = "colon step, adult anatomy, dt = 1 ms (median of 21 blocks of 200 steps)\n";
  for (int n : sizes) {
    ColonParams p = params.colon;
    p.control_point_count = n;
    const ColonModel model = buildColonModel(anatomy, p);
    us.push_back(medianStepMicros(model, 1e-3, 21, 200));
    char line[128];
    std::snprintf(line, sizeof line, "  n = %4d control points: %8.2f us per step (%.3f us per point)\n", n,
                  us.back(), us.back() / n);
    text += line;
  }
  char line[128];
  std::snprintf(line, sizeof line, "  ratio 400 / 50 points: %.2f (8.00 would be linear)\n", us.back() / us.front());
  text += line;
  BenchOutput out;
  out.json = {{"benchmark", "colon"},
              {"dt_s", 1e-3},
              {"n_control_points", sizes},
              {"us_per_step", us},
              {"ratio_400_over_50", us.back() / us.front()}};
  out.text = text;
  return out;
}

}  // namespace colosim
