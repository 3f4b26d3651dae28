// The interactive trainer's window (colosim train): a GLFW window on the calling thread
// polls the keyboard and gamepad and draws the onboard and global views with Dear ImGui
// screens over them (a start screen, the live overlay with the scope-shape inset, the
// score card); the physics loop (trainer/interactive.h) steps the colon + scope in real
// time on its own thread and records the session. docs/trainer-window.md.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainer/interactive.h"
#include "trainer/scenario.h"

namespace colosim {

/// The keys and gamepad controls, for --help.
extern const char* const kTrainKeyHelp;

/// A gamepad as GLFW's standard layout reads it (the SDL game-controller mapping).
struct GamepadState {
  /// left stick x, y; right stick x, y (in [-1, 1]; +y is down, as GLFW gives it); left
  /// and right trigger.
  std::array<float, 6> axes{};
  /// A, B, X, Y, left and right bumper, Back, Start, Guide, left and right stick pressed,
  /// d-pad up, right, down, left (GLFW_GAMEPAD_BUTTON_* order).
  std::array<bool, 15> buttons{};
};

/// Reads a gamepad once a frame: fills `state` (and `name`, when empty) and returns true
/// when there is one.
using GamepadReader = std::function<bool(GamepadState* state, std::string* name)>;

struct TrainWindowOptions {
  int width_px = 1280, height_px = 480;  ///< window size [px]
  /// Open on the start screen (choose the scenario, preselected, and the patient position;
  /// read the goal and the keys); false: the session of the given scenario starts at once.
  bool start_screen = false;
  /// explicit session file (must not exist); empty: a new file in record_dir. Sessions
  /// after the first (restart) go next to it as NAME-2.jsonl, NAME-3.jsonl, ...
  std::string record;
  std::string record_dir = "sessions";
  std::string view = "both";             ///< at the start: onboard, global or both
  double quit_after_s = -1;              ///< wall seconds from the first frame shown; negative: until the window closes
  bool autopilot = false;                ///< the handle follows the scenario's script
  int render_threads = -1;               ///< LP_NUM_THREADS for llvmpipe; 0: Mesa's default; -1: cores - 1
  double render_scale = 0.7;             ///< onboard view drawn at this fraction of its size (render/camera.h)
  std::string screenshot;                ///< PNG of the last frame (a new file); empty: none
  std::string colosim_version;           ///< recorded in the session header
  /// Where the gamepad is read from; empty: the first joystick GLFW has a gamepad mapping
  /// for. Tests drive the window with a scripted gamepad through it.
  GamepadReader gamepad;
  /// Called once a frame with the steps the session on screen has taken (-1: no session);
  /// tests pace a scripted gamepad on the simulation's progress with it.
  std::function<void(long steps)> on_frame;
};

/// What a window session leaves, for the exit summary: the last session's figures, and
/// the list of every session recorded.
struct TrainWindowResult {
  std::string session_path;            ///< the last session ("" when none was started)
  std::string scenario;                ///< its scenario's name
  std::string patient_position;        ///< its patient position
  std::string ended_by;                ///< how it ended: end, restart, close, quit_after, error
  std::vector<std::string> sessions;   ///< every session recorded, in order
  std::vector<std::string> screens;    ///< the screens shown, in order (start, session, score_card)
  nlohmann::json score_card;           ///< the last score card shown (scoreCardJson), null when none
  PhysicsLoopResult loop;
  double dt_s = 0;                     ///< the simulation's time step [s]
  long frames = 0;
  double frames_per_s = 0;
  double frame_ms_median = 0;
  double draw_cpu_ms_per_frame = 0;    ///< CPU time of everything but the physics thread a frame [ms]
  double load_average_1min = 0;        ///< at the start
  int framebuffer_width_px = 0, framebuffer_height_px = 0;
  std::string view;                    ///< at the end
};

/// Runs the trainer window on `scenario` (preselected on the start screen) until it is
/// closed (Q, or Escape on the start screen or score card), quit_after_s passes or a
/// physics loop stops on an error. Every session is recorded; restart starts a new one.
/// InputError before any window or file is opened when the screenshot or session file
/// exists or a shipped scenario or expert session cannot be read.
TrainWindowResult runTrainWindow(const Scenario& scenario, const TrainWindowOptions& options);

}  // namespace colosim
