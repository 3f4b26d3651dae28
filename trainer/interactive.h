// Interactive sessions (colosim train): the operator's controls turned into handle inputs,
// and the physics loop that steps a simulation in real time on its own thread, records
// exactly the input every step used and publishes snapshots for the draw thread.
// No window and no GL here: tests drive the same loop headless with scripted controls.
#pragma once

#include <atomic>
#include <chrono>
#include <exception>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/handle_input.h"
#include "core/scope_model.h"
#include "core/spline.h"
#include "trainer/scenario.h"
#include "trainer/score.h"
#include "trainer/session.h"
#include "trainer/simulation.h"

namespace colosim {

/// What the operator asks for at one instant: how fast each handle input changes.
struct HandleRates {
  double insertion_m_per_s = 0.0;         ///< + = push in, - = pull out [m/s]
  double rotation_rad_per_s = 0.0;        ///< + = clockwise seen by the operator [rad/s]
  double knob_updown_rad_per_s = 0.0;     ///< + = tip up [rad/s]
  double knob_leftright_rad_per_s = 0.0;  ///< + = tip right [rad/s]
  /// Knobs back to neutral at knob_return_rad_per_s (overrides the knob rates).
  bool centre_knobs = false;
  double knob_return_rad_per_s = 1.5;     ///< [rad/s]
  /// The variable-stiffness level the operator chose (HandleInput::stiffness_level); -1:
  /// none chosen, the previous input's is kept.
  int stiffness_level = -1;
};

/// The range of every handle input.
struct HandleLimits {
  double insertion_max_m = 1.6;                          ///< [m]; the minimum is 0
  double rotation_max_rad = 1.0e6;                       ///< |rotation| bound of session files [rad]
  double knob_updown_max_rad = kKnobUpDownMax_rad;       ///< [rad]
  double knob_leftright_max_rad = kKnobLeftRightMax_rad; ///< [rad]
};

/// The limits the scope model accepts: insertion up to (K - 1) h (clampHandleInput), the
/// knobs' stops, and the rotation bound of session files (trainer/handle_io.h).
HandleLimits handleLimitsOf(const ScopeModel& scope);

/// One step of the operator's controls: prev + dt_s * rates, each input clamped to its
/// range (a knob pushed past its stop stays at the stop). Non-finite rates count as 0.
/// The stiffness level is the rates' when they name one, else the previous input's.
HandleInput integrateHandle(const HandleInput& prev, const HandleRates& rates, double dt_s,
                            const HandleLimits& limits);

/// The level a press of the stiffness key (F, the gamepad's right stick button) switches
/// to: the next of the scope's variable-stiffness levels after the one in effect (from the
/// last back to the first); -1 on a scope without a variable-stiffness section.
int nextStiffnessLevel(const ScopeModel& scope, int current_level);

/// The state of the controls at one poll of the keyboard and the gamepad.
struct ControlState {
  // Keys held down.
  bool push = false, pull = false;              ///< insertion
  bool rotate_cw = false, rotate_ccw = false;   ///< axial rotation
  bool tip_up = false, tip_down = false;        ///< up/down knob
  bool tip_left = false, tip_right = false;     ///< left/right knob
  bool fast = false;                            ///< every rate times ControlSpeeds::fast_factor
  bool centre_knobs = false;                    ///< knobs back to neutral
  // Gamepad sticks in [-1, 1] (0 without a gamepad), + = push, clockwise, up, right.
  double axis_insertion = 0.0, axis_rotation = 0.0, axis_updown = 0.0, axis_leftright = 0.0;
};

/// Full-scale speeds of the controls.
struct ControlSpeeds {
  double insertion_m_per_s = 0.03;  ///< about the 1-5 cm/s of a clinical insertion [m/s]
  double rotation_rad_per_s = 1.5;  ///< about a quarter turn per second [rad/s]
  double knob_rad_per_s = 1.5;      ///< [rad/s]
  double fast_factor = 3.0;         ///< [-]
  double dead_zone = 0.15;          ///< stick deflection ignored around the centre [-]
};

/// Keys give full speed, sticks proportional speed beyond the dead zone (rescaled so that
/// full deflection is full speed); keys and sticks add, then saturate at full speed.
HandleRates ratesFromControls(const ControlState& c, const ControlSpeeds& speeds = {});

/// HandleRates shared between the thread that polls the controls and the physics thread.
class SharedRates {
 public:
  void set(const HandleRates& r) {
    std::lock_guard<std::mutex> lock(mutex_);
    rates_ = r;
  }
  HandleRates get() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return rates_;
  }

 private:
  mutable std::mutex mutex_;
  HandleRates rates_;
};

/// Where each step's handle input comes from: called on the physics thread at the boundary
/// before step `step` (counted from 0) with the input the previous step used (for step 0,
/// the start input). What it returns is what the step uses and what the session records.
using InputSource = std::function<HandleInput(long step, const HandleInput& previous)>;

/// The operator's source for a scenario: the scenario's script during its set-up (start
/// kind "scripted": the first until_s seconds, e.g. forming the alpha loop), then the
/// operator's rates integrated step by step. With `autopilot`, the whole script (a demo,
/// and a moving session for smoke tests). `rates` is read at every step. dt_s: the time
/// step of the simulation the source feeds (Simulation::dt_s) [s].
InputSource operatorSource(const Scenario& scenario, double dt_s, const HandleLimits& limits,
                           const SharedRates& rates, bool autopilot = false);

/// What the draw thread needs of one state, copied out of the physics thread.
struct Snapshot {
  long steps = -1;          ///< steps done (0: the start state; -1: none yet)
  Telemetry telemetry;      ///< of the last step (the start state's before any)
  bool has_scene = false;   ///< `scene` is set (the simulation has something to draw)
  SceneView scene;
};
/// Fills `out` from a simulation (Simulation::scene).
void takeSnapshot(const Simulation& sim, long steps, Snapshot& out);

struct PhysicsLoopOptions {
  /// Pace the steps on steady_clock, step k due at k dt after the start (sleep until
  /// then; dt: the simulation's time step); false: as fast as possible (tests, headless).
  bool real_time = true;
  /// Behind the clock by more than this many steps: give up catching up, drop the lost
  /// time (the simulation then runs late against the wall clock) and say so once.
  long max_catch_up_steps = 50;
  /// Stop after this many steps (negative: only when stop() is called).
  long max_steps = -1;
};

/// Measurements of a loop, for the exit summary and --json.
struct PhysicsLoopStats {
  long steps = 0;
  double wall_s = 0.0;              ///< from the first step's start to the loop's end [s]
  double steps_per_s = 0.0;         ///< steps / wall_s [1/s]
  long dropped_steps = 0;           ///< steps of simulated time given up when behind [1]
  int drop_episodes = 0;            ///< times it gave up catching up [1]
  double busy_fraction = 0.0;       ///< time spent stepping / wall_s [-]
  double step_ms_median = 0.0;      ///< of the step (simulation + recording + snapshot) [ms]
  double step_ms_max = 0.0;         ///< [ms]
  long max_lag_steps = 0;           ///< largest lag behind the clock seen at a step boundary [1]
  double cpu_s = 0.0;               ///< CPU time of the loop's thread over the loop [s]
  double paused_s = 0.0;            ///< wall time spent paused (in wall_s, not in steps_per_s) [s]
  int pauses = 0;                   ///< times the loop was paused [1]
};

/// What a finished loop leaves.
struct PhysicsLoopResult {
  long steps = 0;
  uint64_t final_state_hash = 0;
  nlohmann::json scores;  ///< Scorer::json() of the session
  PhysicsLoopStats stats;
};

/// Steps `sim` with the inputs of `source`, one step after another, on its own thread
/// (start/stop) or on the caller's (run). Every step goes through stepAndRecord
/// (trainer/replay.h), as colosim run and replay do, so that the recording replays
/// bit-identically. After every step it publishes a snapshot for the draw thread; the
/// lock is held only to swap buffers, so drawing never holds physics up for long.
class PhysicsLoop {
 public:
  /// `writer` (may be null) records the session; `on_warning` (may be empty) receives the
  /// loop's one-off messages (falling behind), from the physics thread.
  PhysicsLoop(Simulation& sim, const ScoreOptions& scoring, SessionWriter* writer, InputSource source,
              const PhysicsLoopOptions& options = {}, std::function<void(const std::string&)> on_warning = {});
  ~PhysicsLoop();  ///< stops and joins the thread (without writing the end line)
  PhysicsLoop(const PhysicsLoop&) = delete;
  PhysicsLoop& operator=(const PhysicsLoop&) = delete;

  /// Starts the loop on its own thread.
  void start();
  /// Asks the loop to stop at the next step boundary and waits for it.
  void stop();
  /// Runs the loop on the calling thread until max_steps or stop().
  void run();
  /// True while the loop thread runs (false once it reached max_steps or was stopped).
  bool running() const { return running_; }

  /// Asks the loop to pause (no step is taken, simulated time stands still) or to go on,
  /// at the next step boundary. The loop records each change as a session event "paused"
  /// or "resumed" after the steps done so far, so the session says when the trainee
  /// paused; the trajectory does not depend on it (the session is indexed by step, and
  /// real-time pacing restarts from the resume instead of catching up).
  void setPaused(bool paused) { pause_requested_ = paused; }
  /// The loop is paused (it has seen the request and stopped stepping).
  bool paused() const { return paused_; }

  /// Asks for the assistance `a` (AssistInput: the assistant's abdominal pressure, the
  /// patient's position) from the next step boundary on. The loop applies it to the
  /// simulation there and records it as a session assist line, so the replay reproduces it.
  void requestAssist(const AssistInput& a) {
    std::lock_guard<std::mutex> lock(assist_mutex_);
    assist_requested_ = a;
  }

  /// Copies the newest published snapshot into `out` when it is newer than out.steps
  /// (or `out` has none yet); returns whether it copied.
  bool latest(Snapshot& out);

  /// After the loop ended: the end line (final state hash and scores as summary) written
  /// when recording, the scores and the measurements. Call once. When a step threw on
  /// the loop's thread, rethrows that error instead and writes no end line (the session
  /// then replays up to its last checkpoint, as after a crash).
  /// `ended_by` (optional) says in the end line's summary how the session ended
  /// (interactive.ended_by, e.g. "end", "restart", "close", "quit_after").
  PhysicsLoopResult finish(const std::string& ended_by = "");

 private:
  void publish();

  Simulation& sim_;
  Scorer scorer_;
  SessionWriter* writer_;
  InputSource source_;
  PhysicsLoopOptions options_;
  std::function<void(const std::string&)> on_warning_;
  double dt_s_;  ///< the simulation's time step [s]

  HandleInput input_;  ///< the input of the last step (the start input before any)
  long steps_ = 0;
  PhysicsLoopStats stats_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> running_{false};
  std::atomic<bool> pause_requested_{false};
  std::atomic<bool> paused_{false};
  std::thread thread_;
  std::exception_ptr error_;  ///< what a step threw on the loop's thread

  std::mutex assist_mutex_;
  AssistInput assist_requested_;  ///< guarded by assist_mutex_
  AssistInput assist_;            ///< in force (physics thread)

  std::mutex snapshot_mutex_;
  Snapshot back_;     ///< filled by the physics thread outside the lock
  Snapshot shared_;   ///< the newest published, swapped with back_ under the lock
  bool published_ = false;
  bool finished_ = false;
};

/// A new session file in `dir` (created if missing) named
/// YYYYMMDD-HHMMSS_<scenario>.jsonl from the local time, with -2, -3, ... appended when
/// that name is taken; the file is created empty (exclusively: never an existing file)
/// so that two sessions starting in the same second get different names.
std::string newSessionPath(const std::string& dir, const std::string& scenario_name,
                           std::chrono::system_clock::time_point when = std::chrono::system_clock::now());

}  // namespace colosim
