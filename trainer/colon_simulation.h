// A colon-only simulation: the colon model of core/ stepped under gravity and its
// mesentery. It has no scope: the handle inputs are recorded and echoed in the telemetry
// but move nothing. It lets sessions, replay and scoring run end to end before the scope
// exists, and stays useful as the reference for what the colon alone does.
#pragma once

#include <memory>

#include "core/colon_model.h"
#include "core/colon_state.h"
#include "trainer/simulation.h"

namespace colosim {

/// Mesentery stretch of a colon state [-]: the largest over control points of the lifter
/// force on the point, |(K (q - q0))_i| with K the mesentery stiffness matrix (eq. 4),
/// over the weight the point carries, (M 1)_i g. It is the lifter force per unit length
/// over the colon's weight per unit length: about 1 where the attachments just carry the
/// hanging colon (Telemetry::mesentery_stretch). 0 without gravity. Points held only by
/// the "pelvic" class (the extraperitoneal rectum, fixed in the pelvis, not on a
/// mesentery: 20x stiffer, so a millimetre there would read as a large stretch) are left out.
double mesenteryStretch(const ColonModel& model, const ColonState& state);

class ColonOnlySimulation : public Simulation {
 public:
  /// Loads the scenario's anatomy and parameters (with its overrides) and applies its
  /// start state (trainer/start_state.h: settled, colon shape; no scope, no abdominal
  /// pressure). InputError for unusable files.
  explicit ColonOnlySimulation(const Scenario& scenario);
  void step(const HandleInput& in) override;
  double dt_s() const override { return dt_s_; }
  double time_s() const override { return state_.time_s; }
  uint64_t stateHash() const override { return hashColonState(state_); }
  /// Neutral values where there is no scope: no handle or wall force, the tip at the
  /// anus, the lumen in view, no patches measured (patch_count 0).
  Telemetry telemetry() const override;
  std::vector<SimulationEvent> events() const override;

  const ColonModel& model() const { return model_; }
  const ColonState& state() const { return state_; }

 private:
  ColonModel model_;
  ColonState state_;
  double dt_s_;
  HandleInput last_input_;
};

/// A SimulationFactory building ColonOnlySimulation.
std::unique_ptr<Simulation> makeColonOnlySimulation(const Scenario& scenario);

}  // namespace colosim
