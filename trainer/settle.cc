#include "trainer/settle.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/colon_step.h"

namespace colosim {

SettleSummary settleColon(const ColonModel& model, double duration_s, double dt_s) {
  SettleSummary out;
  out.n_control_points = model.n;
  out.length_m = model.length_m();
  out.duration_s = duration_s;
  out.dt_s = dt_s;
  ColonState state = makeColonState(model);
  out.energy_start_J = colonEnergy(model, state).total();
  const long steps = std::lround(duration_s / dt_s);
  constexpr int kBlock = 100;
  std::vector<double> block_us;
  for (long done = 0; done < steps;) {
    const long todo = std::min<long>(kBlock, steps - done);
    const auto t0 = std::chrono::steady_clock::now();
    for (long k = 0; k < todo; ++k) stepColon(model, state, dt_s);
    const auto t1 = std::chrono::steady_clock::now();
    block_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / todo);
    done += todo;
    if (!state.q.allFinite() || !state.v.allFinite()) {
      out.finite = false;
      break;
    }
  }
  out.steps = steps;
  if (!block_us.empty()) {
    std::nth_element(block_us.begin(), block_us.begin() + block_us.size() / 2, block_us.end());
    out.us_per_step_median = block_us[block_us.size() / 2];
  }
  const ColonEnergy e = colonEnergy(model, state);
  out.energy_end_J = e.total();
  out.kinetic_end_J = e.kinetic_J;
  for (int i = 0; i < model.n; ++i) {
    const double d = (state.q.col(i) - model.q_rest.col(i)).norm();
    if (d > out.max_displacement_m) {
      out.max_displacement_m = d;
      const int seg = std::min(i, model.n - 2);
      out.max_displacement_region = model.region_names[model.segment_region[seg]];
    }
    out.max_speed_end_m_per_s = std::max(out.max_speed_end_m_per_s, state.v.col(i).norm());
  }
  out.finite = out.finite && std::isfinite(out.energy_end_J);
  out.state_hash = hashColonState(state);
  return out;
}

}  // namespace colosim
