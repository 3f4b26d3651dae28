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
#include "trainer/telemetry.h"

namespace colosim {

struct Scenario;

/// Something a step raised, recorded as a session event line (docs/file-formats.md).
struct SimulationEvent {
  std::string name;    ///< lowercase identifier, for example "solver_limited"
  std::string detail;  ///< free text ("" for none)
};

class Simulation {
 public:
  virtual ~Simulation();
  /// Advances one time step (the scenario's dt_s) with the given handle input.
  virtual void step(const HandleInput& in) = 0;
  /// Simulated time [s].
  virtual double time_s() const = 0;
  /// 64-bit hash of the whole physical state: equal hashes mean bit-identical states.
  virtual uint64_t stateHash() const = 0;
  /// Measurements of the last step.
  virtual Telemetry telemetry() const = 0;
  /// Events raised by the last step (for example "solver_limited"), recorded in sessions.
  virtual std::vector<SimulationEvent> events() const { return {}; }
};

/// Builds a simulation ready to run a scenario (its start state applied: for "settled",
/// the settling already done). Throws InputError for unusable assets. Must be safe to
/// call from several threads at once (colosim score builds one per session).
using SimulationFactory = std::function<std::unique_ptr<Simulation>(const Scenario&)>;

}  // namespace colosim
