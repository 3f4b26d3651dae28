// The interactive trainer's window (colosim train): a GLFW window on the calling thread
// polls the keyboard and gamepad and draws the onboard and global views; the physics
// loop (trainer/interactive.h) steps the colon + scope in real time on its own thread and
// records the session.
#pragma once

#include <string>

#include "trainer/interactive.h"
#include "trainer/scenario.h"

namespace colosim {

/// The keys and gamepad controls, for --help.
extern const char* const kTrainKeyHelp;

struct TrainWindowOptions {
  int width_px = 1280, height_px = 480;  ///< window size [px]
  std::string record;                    ///< explicit session file (must not exist); empty: a new file in record_dir
  std::string record_dir = "sessions";
  std::string view = "both";             ///< at the start: onboard, global or both
  double quit_after_s = -1;              ///< wall seconds; negative: until the window closes
  bool autopilot = false;                ///< the handle follows the scenario's script
  int render_threads = -1;               ///< LP_NUM_THREADS for llvmpipe; 0: Mesa's default; -1: cores - 1
  double render_scale = 0.7;             ///< onboard view drawn at this fraction of its size (render/camera.h)
  std::string screenshot;                ///< PNG of the last frame (a new file); empty: none
  std::string colosim_version;           ///< recorded in the session header
};

/// What a window session leaves, for the exit summary.
struct TrainWindowResult {
  std::string session_path;
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

/// Runs a recorded interactive session of `scenario` in a window until it is closed
/// (Escape), quit_after_s passes or the physics loop stops on an error. InputError before
/// any window or file is opened when the screenshot or session file exists.
TrainWindowResult runTrainWindow(const Scenario& scenario, const TrainWindowOptions& options);

}  // namespace colosim
