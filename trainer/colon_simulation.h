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

// How restingColon settles: 100 steps of 10 ms. The implicit step's fixed point is the static
// equilibrium whatever the step, and its damping at 10 ms settles the free colon's sag within
// the second. Measured on free_insertion's patient: a 1 ms step from it moves a point 4.9e-8 m
// (2 s of 2 ms steps: 1.3e-10 m, ten times the cost; 0.5 s of 10 ms: 4.4e-7 m).
constexpr double kRestingSettle_s = 1.0;  ///< [s]
constexpr double kRestingStep_s = 1e-2;   ///< [s]

/// The patient's resting colon [m]: the control points of the colon settled under its
/// model's gravity from its rest shape, with the scope out and no hand on the abdomen
/// (kRestingSettle_s of colon steps of kRestingStep_s). What the mesentery carries there is
/// what it carries without pain (mesenteryStretch).
Eigen::Matrix3Xd restingColon(const ColonModel& model);

/// Mesentery stretch of a colon state [-]: the largest over control points of the lifter
/// force beyond the one the point's lifter has in the resting colon,
/// |(K (q - q_resting))_i| with K the mesentery stiffness matrix (eq. 4), over the weight
/// the point carries, (M 1)_i g. It is that force per unit length over the colon's weight
/// per unit length: 0 in the resting patient, about 1 where a lifter carries its colon's
/// weight again on top of what it carried at rest. Without `resting_q` the lifters' rest
/// positions q0 take its place (the whole lifter force: about 1 where the attachments just
/// carry the hanging colon, and several times that where a firm attachment carries a free
/// region through the colon's tension). 0 without gravity. Points held only by the
/// "pelvic" class (the extraperitoneal rectum, fixed in the pelvis, not on a mesentery:
/// 20x stiffer, so a millimetre there would read as a large stretch) are left out.
double mesenteryStretch(const ColonModel& model, const ColonState& state, const Eigen::Matrix3Xd* resting_q = nullptr);

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
  Eigen::Matrix3Xd resting_q_;  ///< restingColon(model_) [m]
};

/// A SimulationFactory building ColonOnlySimulation.
std::unique_ptr<Simulation> makeColonOnlySimulation(const Scenario& scenario);

}  // namespace colosim
