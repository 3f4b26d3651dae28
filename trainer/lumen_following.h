// The lumen-following controller: an "expert" that decides the handle inputs every
// key_dt_s from the simulation's state, as an endoscopist steers towards the lumen and
// takes a loop out by withdrawing. Shared by tools/trainer_make_free_insertion (which
// writes its keyframes as a scenario script) and design studies (trainer/study.h, the
// "lumen_following" strategy).
#pragma once

#include <deque>
#include <functional>
#include <string>
#include <utility>

#include "core/handle_input.h"
#include "trainer/scenario.h"

namespace colosim {

class WorldSimulation;

/// The controller's settings (defaults: the tool's environment variables' defaults).
struct LumenFollowingOptions {
  double key_dt_s = 0.5;          ///< one decision (keyframe) every key_dt_s [s]
  double speed_m_per_s = 0.02;    ///< insertion and withdrawal speed [m/s]
  double lookahead_m = 0.05;      ///< the knobs point the tip at the centreline this far ahead [m]
  double window_s = 10.0;         ///< loop detection window [s]
  double loop_m = 0.15;           ///< scope pushed in beyond the tip's progress that means a loop [m]
  double withdraw_m = 0.30;       ///< a withdrawal ends after this much came out [m]
  double back_m = 0.02;           ///< ... or once the tip came back this far [m]
  double pull_max_N = 1e9;        ///< the withdrawal pauses while the handle pulls harder [N]
  double done_m = 0.025;          ///< insertion stops once the tip is this close to the caecal pole [m]
  double max_knob_change_rad = 0.4;  ///< largest knob change per keyframe [rad]
  /// The operator stiffens a variable-stiffness scope to this level from stiffen_from_s on
  /// (HandleInput::stiffness_level); -1: the level in force is kept.
  int stiffness_level = -1;
  double stiffen_from_s = 0.0;    ///< [s]
};

/// The knobs that point the tip at the colon centreline lookahead_m ahead of it (towards
/// the caecum, rest arclength; tip_arclength_m: the telemetry's, where the tip is along the
/// colon now [m]), as an endoscopist steers towards the lumen: `cur` with its
/// knobs moved by at most max_knob_change_rad each, within the design's stops, rounded to
/// 1e-4 rad. Unchanged while the bending section is not wholly inside.
HandleInput steerTowardsLumen(const WorldSimulation& sim, double tip_arclength_m, const HandleInput& cur,
                              double lookahead_m, double max_knob_change_rad);

/// Replaces the knobs of the scenario's script from `from_s` on by an endoscopist's
/// steering (steerTowardsLumen, decided every key_dt_s from the state), keeping its
/// insertion and rotation, stepping `sim` (built from `scenario`, at time 0) to the
/// scenario's end: the keyframes before from_s are kept, and from from_s on there is one
/// keyframe at every multiple of key_dt_s after from_s and at every keyframe time of the
/// script, whose insertion and rotation are the script's there (rounded to 1e-6 m and rad)
/// and whose knobs are decided from the state at the keyframe before. Stepped with the new
/// script's interpolation, so the scenario replays the same run. `on_step` gets the
/// simulation after every step. Returns the number of steps.
long runWithLumenSteering(Scenario& scenario, WorldSimulation& sim, double from_s, double key_dt_s = 0.5,
                          double lookahead_m = 0.05, double max_knob_change_rad = 0.4,
                          const std::function<void(const WorldSimulation&)>& on_step = {});

/// Decides keyframes from the state. Call next() at t0, t0 + key_dt_s, ... with the
/// simulation stepped (with scriptedInput over the keyframes so far) up to that time; it
/// returns the keyframe at t + key_dt_s. Deterministic: the same states give the same
/// keyframes. Times and inputs are rounded to 1e-4 (s, m, rad) so that the keyframes
/// written to a scenario file replay the same run.
class LumenFollowing {
 public:
  /// `sim` is the simulation it will drive (its models are read here).
  LumenFollowing(const WorldSimulation& sim, const LumenFollowingOptions& options = {});
  /// The keyframe at t_s + key_dt_s from the state at t_s and the input in force (`current`,
  /// the last keyframe's). `log`, when set, receives one line per decision that changes the
  /// mode (advance, withdraw), without a trailing newline.
  Keyframe next(const WorldSimulation& sim, double t_s, const HandleInput& current,
                const std::function<void(const std::string&)>& log = {});
  int withdrawals() const { return withdrawals_; }
  const LumenFollowingOptions& options() const { return o_; }

 private:
  LumenFollowingOptions o_;
  double max_in_m_ = 0;  ///< the scope's insertable length [m]
  size_t window_ = 0;    ///< keyframes in window_s
  enum Mode { kAdvance, kWithdraw, kDone } mode_ = kAdvance;
  std::deque<std::pair<double, double>> history_;  ///< (insertion, tip arclength) per keyframe [m]
  double withdraw_from_L_ = 0, withdraw_from_s_ = 0;
  int withdrawals_ = 0, paused_ = 0;
};

/// Replaces the scenario's script from `from_s` on by the controller's keyframes until
/// end_s, stepping `sim` (built from `scenario`, at time 0) until end_s: the keyframes up to
/// from_s are kept and one at from_s added (the script's input there), then the controller
/// decides every key_dt_s. `on_step` gets every step's telemetry. Returns the number of
/// steps done; scenario.script holds the keyframes, scenario.duration_s the last one's time.
struct LumenFollowingHooks {
  /// After every step, with the simulation.
  std::function<void(const WorldSimulation&)> on_step;
  /// Before every decision, with its time [s] and the input in force.
  std::function<void(double t_s, const HandleInput& current)> on_decision;
  /// The controller's mode changes (LumenFollowing::next's log).
  std::function<void(const std::string&)> log;
  /// The last keyframe may lie up to key_dt_s after end_s: false stops the simulation at
  /// end_s, true steps on to that keyframe (trainer_make_free_insertion, whose script ends
  /// there).
  bool step_to_last_keyframe = false;
};
long runLumenFollowing(Scenario& scenario, WorldSimulation& sim, double from_s, double end_s,
                       const LumenFollowingOptions& options, const LumenFollowingHooks& hooks = {});

}  // namespace colosim
