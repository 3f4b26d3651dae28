#include "trainer/settle.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/colon_step.h"
#include "trainer/start_state.h"

namespace colosim {

SettleSummary settleColon(const WorldModel& world, double duration_s, double dt_s) {
  const ColonModel& model = world.colon;
  SettleSummary out;
  out.n_control_points = model.n;
  out.length_m = model.length_m();
  out.duration_s = duration_s;
  out.dt_s = dt_s;
  out.energy_start_J = colonEnergy(model, makeColonState(model)).total();
  const long steps = std::lround(duration_s / dt_s);
  // Every block of kBlock steps (the last may be shorter): its time per step, and a stop
  // on a non-finite state.
  constexpr int kBlock = 100;
  std::vector<double> block_us;
  auto block_start = std::chrono::steady_clock::now();
  long block_first = 0;
  auto observe = [&](long done, const ColonState& s) {
    if (done % kBlock != 0 && done != steps) return true;
    const auto now = std::chrono::steady_clock::now();
    block_us.push_back(std::chrono::duration<double, std::micro>(now - block_start).count() / (done - block_first));
    block_start = now, block_first = done;
    out.finite = s.q.allFinite() && s.v.allFinite();
    return out.finite;
  };
  StartSpec spec;
  spec.dt_s = dt_s;
  spec.settle_s = duration_s;
  StartState start = makeStartState(world, spec, nullptr, observe);
  ColonState& state = start.state.colon;
  state.time_s = start.settled_clock_s;  // the summary's state is the settling's own, clock included
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
