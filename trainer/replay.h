// Running a scenario's script (and recording it), replaying a session, scoring many
// sessions at once: the library behind `colosim run/replay/score`.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainer/scenario.h"
#include "trainer/session.h"
#include "trainer/simulation.h"

namespace colosim {

/// Optional observers of a run or replay.
struct RunHooks {
  /// After every step, with that step's telemetry.
  std::function<void(const Telemetry&)> on_step;
  /// Every frame_every_steps steps (and after step 0's state, before any step), with the
  /// simulation: where the renderer writes frames.
  std::function<void(const Simulation&, long steps_done)> on_frame;
  long frame_every_steps = 0;
  /// Progress: steps done so far, every 1000 steps and at the end.
  std::function<void(long steps_done)> on_progress;
};

/// One step with everything around it, shared by run, replay and interactive sessions so
/// that they cannot differ: records the input of step `step` (writer, when given), steps,
/// scores the telemetry, records the simulation's events and a checkpoint when due, then
/// calls the hooks.
void stepAndRecord(Simulation& sim, const HandleInput& in, long step, Scorer& scorer, SessionWriter* writer,
                   const RunHooks& hooks = {});

/// The header a recording of this scenario starts with.
SessionHeader sessionHeaderFor(const Scenario& scenario, const std::string& colosim_version);

struct RunResult {
  long steps = 0;
  uint64_t final_state_hash = 0;
  nlohmann::json scores;  ///< Scorer::json() of the run
};

/// Runs the scenario's scripted inputs on `sim` for `steps` steps (scenario.steps() when
/// negative), scoring them, and records the session when `writer` is given (inputs as they
/// change, a checkpoint per simulated second, the simulation's events, the end line with
/// the scores as summary).
RunResult runScenario(const Scenario& scenario, Simulation& sim, SessionWriter* writer,
                      const RunHooks& hooks = {}, long steps = -1);

/// A session read and checked against what it refers to, ready to replay.
struct ReplayPlan {
  Session session;
  Scenario scenario;  ///< with the session's dt_s and seed
  std::vector<std::string> warnings;  ///< scenario, parameter or anatomy files changed since recording
};
/// Reads the session and its scenario; InputError (file and line) for a bad session or
/// scenario, so that every input is validated before any work or output.
ReplayPlan planReplay(const std::string& session_path);

struct ReplayResult {
  std::string file;
  std::string scenario;           ///< the scenario id of the session's header
  long steps = 0;                 ///< steps re-simulated
  uint64_t final_state_hash = 0;  ///< after them
  bool complete = false;          ///< the session had its end line
  bool truncated = false;
  std::string message;            ///< the reader's message for a truncated session
  int checkpoints_checked = 0;
  /// First disagreement with the recording ("" when none): a checkpoint or the end hash.
  std::string mismatch;
  bool final_hash_checked = false;  ///< complete sessions only
  nlohmann::json scores;
  std::vector<std::string> warnings;
  bool hashOk() const { return mismatch.empty(); }
};

/// Re-simulates the recorded inputs on `sim` (built by a factory from plan.scenario),
/// compares every checkpoint and the final state hash with the recording, and scores.
ReplayResult replay(const ReplayPlan& plan, Simulation& sim, const RunHooks& hooks = {});

/// Replays and scores many sessions on `threads` worker threads (0: every core).
/// Every session and scenario is read and checked first (InputError before any
/// simulation); each worker reads its session again when it starts it, so memory holds
/// one session per thread. Results
/// come in the order given and do not depend on the number of threads. `on_progress`
/// receives (steps done, steps total) over all sessions, from the worker threads.
/// `add_hooks`, when given, is called on the worker thread before each session's replay
/// with the session's index and plan, to add observers (on_step, on_frame) to its hooks
/// (a report's timelines and views); their progress hook is the batch's.
using SessionHooksFactory = std::function<void(size_t index, const ReplayPlan& plan, RunHooks& hooks)>;
std::vector<ReplayResult> replaySessions(const std::vector<std::string>& session_paths,
                                         const SimulationFactory& factory, unsigned threads = 0,
                                         const std::function<void(long, long)>& on_progress = {},
                                         const SessionHooksFactory& add_hooks = {});

}  // namespace colosim
