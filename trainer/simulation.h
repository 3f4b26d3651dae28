// What sessions, replay and scoring need from a simulation, behind a small interface so
// that they do not depend on which simulation runs (colon and scope with contacts, the
// colon alone, or a test's fake).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/handle_input.h"
#include "core/spline.h"
#include "trainer/assist_input.h"
#include "trainer/telemetry.h"

namespace colosim {

struct Scenario;
struct ColonModel;

/// What a renderer draws of one state (render/renderer.h): the colon and the scope.
struct SceneView {
  /// The colon's model (radii, regions; its rest shape frames the global view). It does
  /// not change while the simulation runs, so a copied SceneView may keep pointing at it.
  const ColonModel* colon = nullptr;
  Points colon_q;                        ///< colon control points (3 x n) [m]
  std::vector<Vec3> scope_centreline_m;  ///< from outside the anus to the tip [m]
  double scope_radius_m = 0.0;           ///< [m]
  double tip_light_reach_m = 0.02;       ///< the tip light (ScopeParams::tip_light_reach_m) [m]
  Vec3 p_WTip_m = Vec3::Zero();          ///< scope tip [m]
  Mat3 R_WTip = Mat3::Identity();        ///< tip segment frame (d1, d2 up, d3 forward)
};

/// Something a step raised, recorded as a session event line (docs/file-formats.md).
struct SimulationEvent {
  std::string name;    ///< lowercase identifier, for example "solver_limited"
  std::string detail;  ///< free text ("" for none)
};

class Simulation {
 public:
  virtual ~Simulation();
  /// Advances one time step of dt_s() with the given handle input.
  virtual void step(const HandleInput& in) = 0;
  /// The time step [s], fixed when the simulation is built (from its start specification,
  /// trainer/start_state.h): drivers pace, sample scripts and convert steps to time with it.
  virtual double dt_s() const = 0;
  /// Simulated time [s].
  virtual double time_s() const = 0;
  /// 64-bit hash of the whole physical state: equal hashes mean bit-identical states.
  virtual uint64_t stateHash() const = 0;
  /// Measurements of the last step.
  virtual Telemetry telemetry() const = 0;
  /// The assistance in force from the next step on (AssistInput). A simulation without a
  /// patient to press or turn (the colon alone, a test's fake) ignores it. An unknown
  /// position is an InputError naming it.
  virtual void assist(const AssistInput& a) { (void)a; }
  /// Events raised by the last step (for example "solver_limited"), recorded in sessions.
  virtual std::vector<SimulationEvent> events() const { return {}; }
  /// What to draw of the current state into `out`; false (out untouched) when this
  /// simulation has nothing to draw (the colon alone, a test's fake).
  virtual bool scene(SceneView& out) const {
    (void)out;
    return false;
  }
};

/// Builds a simulation ready to run a scenario (its start state applied: for "settled",
/// the settling already done). Throws InputError for unusable assets. Must be safe to
/// call from several threads at once (colosim score builds one per session).
using SimulationFactory = std::function<std::unique_ptr<Simulation>(const Scenario&)>;

}  // namespace colosim
