// The start state of a simulation, built in one place from a start specification: the
// colon settled under gravity, a region of it shaped, the abdominal pressure resolved to
// spline segments and the scope threaded along the colon to the first handle input
// (docs/file-formats.md, "Scenarios": start, abdominal_pressure). The world simulation,
// the colon-only simulation, `colosim run settle` and the insertion replay all start here.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/handle_input.h"
#include "core/world.h"
#include "trainer/scenario.h"

namespace colosim {

/// What a start state is built from.
struct StartSpec {
  double dt_s = 1e-3;        ///< time step of the settling [s]
  /// The colon first settles this long under gravity with the scope out [s] (0: none);
  /// its clock then starts again at 0.
  double settle_s = 0.0;
  /// One region of the colon placed along the curve through shape_points_m (empty: none;
  /// ScenarioStart::shape_region).
  std::string shape_region;
  std::vector<Vec3> shape_points_m;  ///< waypoints in the patient frame [m]
  std::vector<AbdominalPressure> abdominal_pressure;  ///< in scenario order
  std::vector<PatientTurn> patient_turns;             ///< in time order (applied by WorldSimulation)
  /// The scope is threaded along the colon to this input's insertion and rotation, and
  /// holds it (clamped to the scope model's range).
  HandleInput first_input;
  /// After threading, the world runs this long with the handle held at first_input, so
  /// that the bent scope comes to rest against the wall before the clock starts [s]
  /// (0: none). Measured on sigmoid_untwist and sigmoid_push: without it the closed-joint
  /// start still engaged a solver limit in 2 steps; with 0.5 s (or 1 s) none, and the
  /// handle force stays below 2 N (tests/trainer/start_state_test.cc).
  double relax_s = 0.5;
  std::string file;  ///< the scenario file errors name with their line ("": none)
};

/// A scenario's start: its start state, abdominal pressure and first keyframe's input.
StartSpec startSpecOf(const Scenario& scenario);

/// The spline segments [first, last] of a region of the colon; first = -1 when the anatomy
/// has no such region.
std::pair<int, int> regionSegments(const ColonModel& colon, const std::string& region);

/// An abdominal pressure resolved to the colon's spline segments.
struct PressureSchedule {
  RegionSupport region;  ///< full densities
  double from_s = 0, to_s = 0, ramp_s = 0;  ///< [s]
};

struct StartState {
  /// The state at t = 0; state.support holds one entry per pressure, switched off.
  WorldState state;
  std::vector<PressureSchedule> pressure;  ///< one per StartSpec::abdominal_pressure
  /// The colon's clock at the end of the settling, before it restarted at 0 [s].
  double settled_clock_s = 0.0;
};

/// Called after every settling step with the steps done and the colon; returning false
/// ends the settling there (colosim run settle stops on a non-finite state).
using SettleObserver = std::function<bool(long steps_done, const ColonState& colon)>;

/// Builds the start state of `model` in stages: settle (round(settle_s / dt_s) colon
/// steps, the scope out), colon shape, abdominal pressure, threading, relaxation
/// (round(relax_s / dt_s) world steps with contacts found by `query`, or by an FCL query
/// of its own when null, when the scope was threaded; the clock then starts again at 0).
/// InputError naming the file and line of the key for a region the anatomy does not have
/// or a shape whose ends miss the region's.
StartState makeStartState(const WorldModel& model, const StartSpec& spec, ContactQuery* query = nullptr,
                          const SettleObserver& observe = {});

}  // namespace colosim
