#include "trainer/colon_simulation.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/colon_step.h"
#include "trainer/assets.h"
#include "trainer/scenario.h"
#include "trainer/start_state.h"

namespace colosim {

Simulation::~Simulation() = default;

Eigen::Matrix3Xd restingColon(const ColonModel& model) {
  ColonState s = makeColonState(model);
  const long steps = std::lround(kRestingSettle_s / kRestingStep_s);
  for (long k = 0; k < steps; ++k) stepColon(model, s, kRestingStep_s);
  return s.q;
}

double mesenteryStretch(const ColonModel& model, const ColonState& state, const Eigen::Matrix3Xd* resting_q) {
  const double g_m_per_s2 = model.gravity_m_per_s2.norm();
  if (!(g_m_per_s2 > 0)) return 0.0;
  // Measured after every step: the scratch is kept per thread, the classes compared once
  // per region (not per point and step), so that the measure allocates nothing.
  thread_local std::vector<double> d, f;
  thread_local Eigen::Matrix3Xd force;
  thread_local std::vector<char> pelvic_region;
  d.resize(model.n);
  f.resize(model.n);
  force.resize(3, model.n);
  // Lifter forces at the control points beyond the resting ones: F = K (q - q_resting),
  // one coordinate at a time.
  const Eigen::Matrix3Xd& q_from = resting_q ? *resting_q : model.q_rest;
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < model.n; ++i) d[i] = state.q(c, i) - q_from(c, i);
    model.mesentery_K.multiply(d.data(), f.data());
    for (int i = 0; i < model.n; ++i) force(c, i) = f[i];
  }
  pelvic_region.resize(model.region_mesentery.size());
  for (size_t r = 0; r < model.region_mesentery.size(); ++r) pelvic_region[r] = model.region_mesentery[r] == "pelvic";
  // Pelvic points: a segment of point i's support (its lifter row, segments i-2..i+1) is
  // in a "pelvic" region.
  auto pelvic = [&model](int i) {
    for (int j = std::max(0, i - 2); j <= std::min(model.n - 2, i + 1); ++j)
      if (pelvic_region[model.segment_region[j]]) return true;
    return false;
  };
  double largest = 0.0;
  for (int i = 0; i < model.n; ++i)
    if (!pelvic(i)) largest = std::max(largest, force.col(i).norm() / (model.mass_rowsum_kg(i) * g_m_per_s2));
  return largest;
}

ColonOnlySimulation::ColonOnlySimulation(const Scenario& scenario) : dt_s_(scenario.dt_s) {
  WorldModel world = loadWorldModel(scenario.anatomy_path, scenarioParameters(scenario));
  // The world's start state without the scope or the hand on the abdomen: the colon
  // settled and shaped as the scenario says.
  StartSpec start = startSpecOf(scenario);
  start.abdominal_pressure.clear();
  start.first_input = HandleInput();
  state_ = makeStartState(world, start).state.colon;
  model_ = std::move(world.colon);
  resting_q_ = restingColon(model_);
  if (!scenario.script.empty()) last_input_ = scenario.script.front().input;
}

void ColonOnlySimulation::step(const HandleInput& in) {
  last_input_ = in;
  state_.loads.clear();
  stepColon(model_, state_, dt_s_);
}

Telemetry ColonOnlySimulation::telemetry() const {
  Telemetry t;
  t.time_s = state_.time_s;
  t.input = last_input_;
  t.tip_position_m = Vec3::Zero();  // no scope: the tip stays at the anus
  t.tip_to_caecum_m = state_.q.col(model_.n - 1).norm();
  t.mesentery_stretch = mesenteryStretch(model_, state_, &resting_q_);
  regionLengthRatios(model_, state_.q, t.region_length_ratio);
  t.colon_stretch = colonStretch(t.region_length_ratio);
  t.region_names = &model_.region_names;
  return t;
}

std::vector<SimulationEvent> ColonOnlySimulation::events() const {
  if (!state_.solver_ok) return {{"solver_failed", ""}};
  return {};
}

std::unique_ptr<Simulation> makeColonOnlySimulation(const Scenario& scenario) {
  return std::make_unique<ColonOnlySimulation>(scenario);
}

}  // namespace colosim
