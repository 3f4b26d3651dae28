// A small deterministic stand-in for the colon + scope simulation: a tip pulled along
// the colon by a spring towards the insertion, with a sensitive (chaotic) internal
// variable so that any change of input or order shows in the state hash.
#pragma once

#include <cmath>
#include <cstring>
#include <memory>

#include "trainer/scenario.h"
#include "trainer/simulation.h"

namespace colosim::test {

class FakeSimulation : public Simulation {
 public:
  explicit FakeSimulation(const Scenario& s) : dt_s_(s.dt_s), chaos_(0.1 + 1e-3 * s.seed) {}

  void step(const HandleInput& in) override {
    in_ = in;
    const double k = 40.0, c = 8.0;  // spring [1/s^2] and damping [1/s] of the tip
    v_ += dt_s_ * (k * (in.insertion_m - x_) - c * v_);
    x_ += dt_s_ * v_;
    chaos_ = 3.9 * chaos_ * (1.0 - chaos_) +
             1e-6 * (in.insertion_m + in.rotation_rad + in.knob_updown_rad + in.knob_leftright_rad);
    chaos_ = chaos_ - std::floor(chaos_);
    time_s_ += dt_s_;
    ++steps_;
  }
  /// Raises "solver_limited" once, at step 150, as the real simulation does when its
  /// solver cannot keep up.
  std::vector<SimulationEvent> events() const override {
    if (steps_ == 150) return {{"solver_limited", ""}};
    return {};
  }
  double dt_s() const override { return dt_s_; }
  double time_s() const override { return time_s_; }
  uint64_t stateHash() const override {
    const double vals[4] = {x_, v_, chaos_, time_s_};
    unsigned char bytes[sizeof vals];
    std::memcpy(bytes, vals, sizeof vals);
    uint64_t h = 14695981039346656037ull;
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
    return h;
  }
  Telemetry telemetry() const override {
    Telemetry t;
    t.time_s = time_s_;
    t.input = in_;
    t.handle_force_N = 40.0 * (in_.insertion_m - x_);
    t.handle_torque_Nm = 0.1 * std::sin(in_.rotation_rad);
    t.wall_force_peak_N = 5.0 * std::abs(in_.knob_updown_rad);
    t.tip_position_m = Vec3(x_, 0, 0);
    t.tip_to_caecum_m = std::abs(1.0 - x_);
    t.mesentery_stretch = 10.0 * std::abs(in_.insertion_m - x_);
    t.colon_stretch = 0.06 * std::abs(in_.insertion_m - x_);  // past 0.03 where the stretch passes 5
    t.loop_turns = in_.rotation_rad / (2 * 3.14159265358979323846);
    t.tip_against_wall = in_.knob_updown_rad > 1.0;
    t.lumen_visible = !t.tip_against_wall;
    t.patch_count = 100;
    const int id = static_cast<int>(std::floor(x_ * 100));
    if (id >= 0 && id < 100) t.patches_seen.push_back(id);
    return t;
  }

 private:
  double dt_s_;
  double x_ = 0, v_ = 0, chaos_, time_s_ = 0;
  long steps_ = 0;
  HandleInput in_;
};

inline std::unique_ptr<Simulation> makeFake(const Scenario& s) { return std::make_unique<FakeSimulation>(s); }

}  // namespace colosim::test
