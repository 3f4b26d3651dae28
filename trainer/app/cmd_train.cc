// colosim train [SCENARIO]: the interactive trainer. A GLFW window on the main thread
// polls the keyboard and gamepad and draws; the physics loop (trainer/interactive.h)
// steps the colon + scope at 1 kHz on its own thread and records the session.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>
#include <vector>

// GLFW must not include the system GL header: the renderer loads GL through glad.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <sys/resource.h>

#include "render/image.h"
#include "render/renderer.h"
#include "render/window.h"
#include "trainer/app/commands.h"
#include "trainer/app/simulation_factory.h"
#include "trainer/interactive.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/strict_json.h"
#include "trainer/world_simulation.h"

namespace colosim::app {

namespace {

constexpr const char* kKeyHelp =
    "Keys (held down; full speed 3 cm/s insertion, 1.5 rad/s rotation and knobs):\n"
    "  W / S  or  Up / Down      push / pull the scope\n"
    "  A / D  or  Left / Right   rotate anticlockwise / clockwise (seen by the operator)\n"
    "  I / K                     tip up / down (up/down knob)\n"
    "  J / L                     tip left / right (left/right knob)\n"
    "  Space                     both knobs back to neutral\n"
    "  Shift                     3x speed\n"
    "  1 / 2 / 3  (V cycles)     onboard / global / split view\n"
    "  mouse on the global view  left drag orbits, right drag pans, wheel zooms\n"
    "  Escape or close button    end the session (the score is printed)\n"
    "Gamepad (when GLFW finds one): left stick up/down push/pull, left stick left/right\n"
    "rotation, right stick the tip knobs, right bumper 3x speed, A centres the knobs, Back\n"
    "cycles the view. The session is recorded without being asked (--record-dir, --record).";

struct TrainOptions {
  std::string scenario = "free_insertion";
  std::string record;                    // explicit session file (must not exist)
  std::string record_dir = "sessions";   // otherwise a new file in this folder
  std::string view = "both";
  std::string size = "1280x480";
  double quit_after_s = -1;              // wall seconds; negative: until the window closes
  bool autopilot = false;
  bool json = false;
  int render_threads = -1;               // LP_NUM_THREADS for llvmpipe; 0: Mesa's default; -1: auto
  double render_scale = 0.7;             // onboard view drawn at this fraction of its size, stretched (render/camera.h)
  std::string screenshot;                // PNG of the last frame
};

// Keyboard and gamepad, polled once per frame.
ControlState pollControls(GLFWwindow* w, bool* have_gamepad, std::string* gamepad_name) {
  auto down = [w](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
  ControlState c;
  c.push = down(GLFW_KEY_W) || down(GLFW_KEY_UP);
  c.pull = down(GLFW_KEY_S) || down(GLFW_KEY_DOWN);
  c.rotate_ccw = down(GLFW_KEY_A) || down(GLFW_KEY_LEFT);
  c.rotate_cw = down(GLFW_KEY_D) || down(GLFW_KEY_RIGHT);
  c.tip_up = down(GLFW_KEY_I);
  c.tip_down = down(GLFW_KEY_K);
  c.tip_left = down(GLFW_KEY_J);
  c.tip_right = down(GLFW_KEY_L);
  c.fast = down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT);
  c.centre_knobs = down(GLFW_KEY_SPACE);
  *have_gamepad = false;
  for (int jid = GLFW_JOYSTICK_1; jid <= GLFW_JOYSTICK_LAST; ++jid) {
    GLFWgamepadstate pad;
    if (!glfwJoystickIsGamepad(jid) || !glfwGetGamepadState(jid, &pad)) continue;
    *have_gamepad = true;
    if (gamepad_name->empty()) *gamepad_name = glfwGetGamepadName(jid) ? glfwGetGamepadName(jid) : "gamepad";
    // GLFW's sticks: +y is down.
    c.axis_insertion = -pad.axes[GLFW_GAMEPAD_AXIS_LEFT_Y];
    c.axis_rotation = pad.axes[GLFW_GAMEPAD_AXIS_LEFT_X];
    c.axis_updown = -pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_Y];
    c.axis_leftright = pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_X];
    c.fast = c.fast || pad.buttons[GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER] == GLFW_PRESS;
    c.centre_knobs = c.centre_knobs || pad.buttons[GLFW_GAMEPAD_BUTTON_A] == GLFW_PRESS;
    break;
  }
  return c;
}

double radToDeg(double rad) { return rad * 180.0 / 3.14159265358979323846; }

void drawOverlay(Renderer& r, const Snapshot& s, const ScoreOptions& scoring, double fps, double physics_hz,
                 int width_px, int height_px) {
  const Viewport all{0, 0, width_px, height_px};
  const std::array<float, 4> white{1.0f, 1.0f, 1.0f, 0.95f}, grey{0.8f, 0.8f, 0.8f, 0.8f};
  const Telemetry& t = s.telemetry;
  char line[160];
  int y = 8;
  auto text = [&](const std::array<float, 4>& rgba, int scale = 2) {
    r.drawText(line, 8, y, scale, rgba, all);
    y += 9 * scale;
  };
  std::snprintf(line, sizeof line, "DEPTH %.3f M", t.input.insertion_m);
  text(white);
  std::snprintf(line, sizeof line, "FORCE %+.1f N  TORQUE %+.3f N M", t.handle_force_N, t.handle_torque_Nm);
  text(white);
  std::snprintf(line, sizeof line, "TIME %.1f S", t.time_s);
  text(white);
  std::snprintf(line, sizeof line, "ROTATION %+.0f DEG  TIP UP %+.0f RIGHT %+.0f DEG", radToDeg(t.input.rotation_rad),
                radToDeg(t.input.knob_updown_rad), radToDeg(t.input.knob_leftright_rad));
  text(grey);
  if (std::abs(t.loop_turns) >= scoring.loop_turns) {
    std::snprintf(line, sizeof line, "LOOP %.2f TURNS - PULL BACK AND TORQUE", std::abs(t.loop_turns));
    text({1.0f, 0.25f, 0.2f, 1.0f}, 3);
  }
  std::snprintf(line, sizeof line,
                "PHYSICS %.0f/S  DRAW %.0f FPS    W/S PUSH/PULL  A/D ROTATE  I/K J/L TIP  SPACE CENTRE TIP  "
                "SHIFT FAST  1 2 3 VIEW  ESC END",
                physics_hz, fps);
  r.drawText(line, 8, height_px - 14, 1, grey, all);
}

struct FrameClock {
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::vector<double> frame_ms;
};

// CPU time of the whole process (every thread) [s].
double processCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec + 1e-6 * u.ru_stime.tv_usec;
}

void printScores(const nlohmann::json& scores) {
  std::printf("  scores:\n");
  for (auto it = scores.begin(); it != scores.end(); ++it) {
    if (it.value().is_object() || it.value().is_array()) continue;
    std::printf("    %-34s %s\n", it.key().c_str(), it.value().dump().c_str());
  }
}

int runTrain(const TrainOptions& o) {
  // Every input is read and checked before a window or a file is opened.
  const Scenario scenario = findScenario(o.scenario);
  int width = 0, height = 0;
  char extra = 0;
  if (std::sscanf(o.size.c_str(), "%dx%d%c", &width, &height, &extra) != 2 || width < 64 || height < 64 ||
      width > 8192 || height > 8192)
    throw InputError("--size: expected WxH in pixels (64..8192), got '" + o.size + "'");
  if (!o.screenshot.empty() && std::filesystem::exists(o.screenshot))
    throw InputError(o.screenshot + ": exists (a screenshot never overwrites a file)");
  if (!o.record.empty() && std::filesystem::exists(o.record))
    throw InputError(o.record + ": exists (a session never overwrites a file); choose a new name or --record-dir");
  // llvmpipe rasterises on as many threads as cores by default; on 2 cores its threads
  // then take turns with the physics thread and physics falls behind. Leaving physics a
  // core of its own kept it at 1000 steps/s at the same frame rate (README, measured).
  int render_threads = o.render_threads;
  if (render_threads < 0 && !std::getenv("LP_NUM_THREADS"))
    render_threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1);
  if (render_threads > 0) setenv("LP_NUM_THREADS", std::to_string(render_threads).c_str(), 1);

  Window window(width, height, "colosim train " + scenario.name);
  Renderer renderer;
  WorldSimulation sim(scenario);
  const std::string session_path = o.record.empty() ? newSessionPath(o.record_dir, scenario.name) : o.record;
  SessionHeader header = sessionHeaderFor(scenario, COLOSIM_VERSION);
  header.mode = "interactive";
  SessionWriter writer(session_path, header);

  SharedRates rates;
  PhysicsLoopOptions loop_options;
  loop_options.dt_s = scenario.dt_s;
  PhysicsLoop loop(sim, scenario.scoring, &writer,
                   operatorSource(scenario, handleLimitsOf(sim.model().scope), rates, o.autopilot), loop_options,
                   [](const std::string& m) { std::fprintf(stderr, "colosim train: warning: %s\n", m.c_str()); });

  const ColonModel& colon = sim.model().colon;
  std::string view = o.view;
  {
    const Points& rest = colon.q_rest;
    window.globalCamera() = frameBox(rest.rowwise().minCoeff(), rest.rowwise().maxCoeff(), 640.0 / 480.0);
  }
  bool have_gamepad = false;
  std::string gamepad_name;
  bool said_gamepad = false;
  bool key_was_down[4] = {false, false, false, false};  // 1, 2, 3, V / Back: act on the press
  Snapshot snap;
  FrameClock clock;
  long frames = 0;
  double shown_fps = 0, shown_physics_hz = 0;
  auto last_rate_time = clock.start;
  long last_rate_frames = 0, last_rate_steps = 0;

  double load_1min = 0;
  getloadavg(&load_1min, 1);
  const double cpu_start_s = processCpuSeconds();
  auto drawFrame = [&] {
    const int fb_w = window.framebufferWidth(), fb_h = window.framebufferHeight();
    if (!snap.has_world || fb_w < 2 || fb_h < 1) return;  // minimised
    ScopeShape shape;
    shape.centreline_m = snap.scope_centreline_m;
    shape.radius_m = snap.scope_radius_m;
    const int view_w = view == "both" ? fb_w / 2 : fb_w;
    drawViews(renderer, colon, snap.colon_q, shape, tipCameraPose(snap.p_WTip_m, snap.R_WTip), view, view_w, fb_h,
              window.globalCamera(), o.render_scale);
    drawOverlay(renderer, snap, scenario.scoring, shown_fps, shown_physics_hz, fb_w, fb_h);
  };
  loop.start();
  try {
    auto frame_start = std::chrono::steady_clock::now();
    while (!window.shouldClose()) {
      window.pollEvents();
      GLFWwindow* w = window.handle();
      if (glfwGetKey(w, GLFW_KEY_ESCAPE) == GLFW_PRESS) glfwSetWindowShouldClose(w, GLFW_TRUE);
      rates.set(ratesFromControls(pollControls(w, &have_gamepad, &gamepad_name)));
      if (have_gamepad && !said_gamepad) {
        std::fprintf(stderr, "colosim train: gamepad: %s\n", gamepad_name.c_str());
        said_gamepad = true;
      }
      // View keys act on the press, not while held.
      bool back = false;
      for (int jid = GLFW_JOYSTICK_1; jid <= GLFW_JOYSTICK_LAST && have_gamepad; ++jid) {
        GLFWgamepadstate pad;
        if (glfwJoystickIsGamepad(jid) && glfwGetGamepadState(jid, &pad)) {
          back = pad.buttons[GLFW_GAMEPAD_BUTTON_BACK] == GLFW_PRESS;
          break;
        }
      }
      const bool now_down[4] = {glfwGetKey(w, GLFW_KEY_1) == GLFW_PRESS, glfwGetKey(w, GLFW_KEY_2) == GLFW_PRESS,
                                glfwGetKey(w, GLFW_KEY_3) == GLFW_PRESS,
                                glfwGetKey(w, GLFW_KEY_V) == GLFW_PRESS || back};
      if (now_down[0] && !key_was_down[0]) view = "onboard";
      if (now_down[1] && !key_was_down[1]) view = "global";
      if (now_down[2] && !key_was_down[2]) view = "both";
      if (now_down[3] && !key_was_down[3]) view = view == "both" ? "onboard" : view == "onboard" ? "global" : "both";
      std::copy(now_down, now_down + 4, key_was_down);
      window.setGlobalViewLeft(view == "both" ? 0.5 : view == "global" ? 0.0 : 1.0);

      loop.latest(snap);
      drawFrame();
      window.swapBuffers();
      ++frames;
      const auto now = std::chrono::steady_clock::now();
      clock.frame_ms.push_back(std::chrono::duration<double, std::milli>(now - frame_start).count());
      frame_start = now;
      // The overlay's rates, over the last half second.
      const double since_s = std::chrono::duration<double>(now - last_rate_time).count();
      if (since_s >= 0.5) {
        shown_fps = (frames - last_rate_frames) / since_s;
        shown_physics_hz = (snap.steps - last_rate_steps) / since_s;
        last_rate_time = now, last_rate_frames = frames, last_rate_steps = snap.steps;
      }
      if (o.quit_after_s >= 0 && std::chrono::duration<double>(now - clock.start).count() >= o.quit_after_s) break;
      if (!loop.running()) break;  // the loop stopped by itself: only on an error
    }
  } catch (...) {
    // Close the session properly (end line) before reporting the error.
    loop.stop();
    try {
      loop.finish();
    } catch (...) {  // the draw error is the one to report
    }
    throw;
  }
  const double draw_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock.start).count();
  loop.stop();
  const double cpu_s = processCpuSeconds() - cpu_start_s;
  const PhysicsLoopResult r = loop.finish();
  if (!o.screenshot.empty()) {
    loop.latest(snap);
    drawFrame();
    writePng(o.screenshot, window.read());
  }
  const double fps = draw_wall_s > 0 ? frames / draw_wall_s : 0.0;
  // Everything but the physics thread draws: the main thread and llvmpipe's rasterisers.
  const double draw_cpu_ms_per_frame = frames > 0 ? 1e3 * (cpu_s - r.stats.cpu_s) / frames : 0.0;
  std::vector<double> sorted = clock.frame_ms;
  std::sort(sorted.begin(), sorted.end());
  const double frame_ms_median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  const char* lp = std::getenv("LP_NUM_THREADS");

  if (o.json) {
    nlohmann::json j{{"scenario", scenario.name},
                     {"session", session_path},
                     {"steps", r.steps},
                     {"simulated_s", r.steps * scenario.dt_s},
                     {"wall_s", r.stats.wall_s},
                     {"physics_steps_per_s", r.stats.steps_per_s},
                     {"dropped_steps", r.stats.dropped_steps},
                     {"physics_busy_pct", 100.0 * r.stats.busy_fraction},
                     {"physics_cpu_pct", r.stats.wall_s > 0 ? 100.0 * r.stats.cpu_s / r.stats.wall_s : 0.0},
                     {"step_ms_median", r.stats.step_ms_median},
                     {"step_ms_max", r.stats.step_ms_max},
                     {"frames", frames},
                     {"frames_per_s", fps},
                     {"frame_ms_median", frame_ms_median},
                     {"draw_cpu_ms_per_frame", draw_cpu_ms_per_frame},
                     {"load_average_1min", load_1min},
                     {"render_scale", o.render_scale},
                     {"window_px", std::to_string(window.framebufferWidth()) + "x" +
                                       std::to_string(window.framebufferHeight())},
                     {"view", view},
                     {"lp_num_threads", lp ? nlohmann::json(lp) : nlohmann::json(nullptr)},
                     {"final_state_hash", hashToHex(r.final_state_hash)},
                     {"scores", r.scores}};
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::printf("colosim train %s: %ld steps (%.3f s simulated) in %.2f s of wall time\n", scenario.name.c_str(),
              r.steps, r.steps * scenario.dt_s, r.stats.wall_s);
  std::printf("  physics              %.1f steps/s (target %.0f), %ld steps dropped, CPU %.0f %% of a core, "
              "step median %.2f ms, max %.2f ms\n",
              r.stats.steps_per_s, 1.0 / scenario.dt_s, r.stats.dropped_steps,
              r.stats.wall_s > 0 ? 100.0 * r.stats.cpu_s / r.stats.wall_s : 0.0, r.stats.step_ms_median,
              r.stats.step_ms_max);
  std::printf("  drawing              %.1f frames/s (%ld frames, median %.1f ms, CPU %.1f ms a frame, %dx%d, %s view%s%s)\n",
              fps, frames, frame_ms_median, draw_cpu_ms_per_frame, window.framebufferWidth(),
              window.framebufferHeight(), view.c_str(), lp ? ", LP_NUM_THREADS=" : "", lp ? lp : "");
  std::printf("  load average         %.2f (1 min, at the start; the machine's other work competes)\n", load_1min);
  std::printf("  final state hash     %s\n", hashToHex(r.final_state_hash).c_str());
  std::printf("  session recorded in  %s\n", session_path.c_str());
  printScores(r.scores);
  return 0;
}

}  // namespace

void addTrainCommand(CLI::App& app, Action& action) {
  auto o = std::make_shared<TrainOptions>();
  CLI::App* cmd = app.add_subcommand("train", "Interactive trainer: drive the scope in a window, recorded")
                      ->footer(kKeyHelp);
  cmd->add_option("SCENARIO", o->scenario, "scenario file, or the name of one in assets/scenarios/")
      ->capture_default_str();
  cmd->add_option("--record", o->record, "record the session into this new file (never overwritten)");
  cmd->add_option("--record-dir", o->record_dir,
                  "otherwise record into a new file YYYYMMDD-HHMMSS_SCENARIO.jsonl in this folder")
      ->capture_default_str();
  cmd->add_option("--view", o->view, "view at the start (keys 1, 2, 3 switch)")
      ->check(CLI::IsMember({"onboard", "global", "both"}))
      ->capture_default_str();
  cmd->add_option("--size", o->size, "window size WxH [px]")->capture_default_str();
  cmd->add_option("--quit-after", o->quit_after_s, "end the session after this many wall seconds (tests, demos)")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_flag("--autopilot", o->autopilot, "the handle follows the scenario's script instead of the controls");
  cmd->add_option("--render-threads", o->render_threads,
                  "rasteriser threads of Mesa's llvmpipe (sets LP_NUM_THREADS; 0: Mesa's default, one per "
                  "core); default: cores - 1, so that physics keeps a core, unless LP_NUM_THREADS is set")
      ->check(CLI::Range(0, 64));
  cmd->add_option("--render-scale", o->render_scale,
                  "draw the onboard view at this fraction of its size and stretch it (its fragment work "
                  "goes with the square; 1: full size)")
      ->check(CLI::Range(0.25, 1.0))
      ->capture_default_str();
  cmd->add_option("--screenshot", o->screenshot, "write the last frame into this new PNG file");
  cmd->add_flag("--json", o->json, "print one JSON object on stdout at the end (rates, session, scores)");
  cmd->callback([&action, o] { action = [o]() -> int { return runTrain(*o); }; });
}

}  // namespace colosim::app
