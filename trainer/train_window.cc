#include "trainer/train_window.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <thread>
#include <vector>

// GLFW must not include the system GL header: the renderer loads GL through glad.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <sys/resource.h>

#include "core/input_error.h"
#include "render/image.h"
#include "render/renderer.h"
#include "render/window.h"
#include "trainer/replay.h"
#include "trainer/scene_drawing.h"
#include "trainer/world_simulation.h"

namespace colosim {

const char* const kTrainKeyHelp =
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

namespace {

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

// CPU time of the whole process (every thread) [s].
double processCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec + 1e-6 * u.ru_stime.tv_usec;
}

// The view keys act on the press, not while held: 1, 2, 3 choose a view, V (or the
// gamepad's Back) cycles them.
class ViewKeys {
 public:
  explicit ViewKeys(std::string view) : view_(std::move(view)) {}
  const std::string& view() const { return view_; }
  void poll(GLFWwindow* w, bool have_gamepad) {
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
    if (now_down[0] && !was_down_[0]) view_ = "onboard";
    if (now_down[1] && !was_down_[1]) view_ = "global";
    if (now_down[2] && !was_down_[2]) view_ = "both";
    if (now_down[3] && !was_down_[3]) view_ = view_ == "both" ? "onboard" : view_ == "onboard" ? "global" : "both";
    std::copy(now_down, now_down + 4, was_down_);
  }

 private:
  std::string view_;
  bool was_down_[4] = {false, false, false, false};  // 1, 2, 3, V / Back
};

// The overlay's rates (frames and physics steps per second), over the last half second.
struct ShownRates {
  double fps = 0, physics_hz = 0;
  std::chrono::steady_clock::time_point since;
  long since_frames = 0, since_steps = 0;
  void update(std::chrono::steady_clock::time_point now, long frames, long steps) {
    const double span_s = std::chrono::duration<double>(now - since).count();
    if (span_s < 0.5) return;
    fps = (frames - since_frames) / span_s;
    physics_hz = (steps - since_steps) / span_s;
    since = now, since_frames = frames, since_steps = steps;
  }
};

// llvmpipe rasterises on as many threads as cores by default; on 2 cores its threads
// then take turns with the physics thread and physics falls behind. Leaving physics a
// core of its own kept it at 1000 steps/s at the same frame rate (README, measured).
void setRenderThreads(int render_threads) {
  if (render_threads < 0 && !std::getenv("LP_NUM_THREADS"))
    render_threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1);
  if (render_threads > 0) setenv("LP_NUM_THREADS", std::to_string(render_threads).c_str(), 1);
}

}  // namespace

TrainWindowResult runTrainWindow(const Scenario& scenario, const TrainWindowOptions& o) {
  // Every input is checked before a window or a file is opened.
  if (!o.screenshot.empty() && std::filesystem::exists(o.screenshot))
    throw InputError(o.screenshot + ": exists (a screenshot never overwrites a file)");
  if (!o.record.empty() && std::filesystem::exists(o.record))
    throw InputError(o.record + ": exists (a session never overwrites a file); choose a new name or --record-dir");
  setRenderThreads(o.render_threads);

  Window window(o.width_px, o.height_px, "colosim train " + scenario.name);
  Renderer renderer;
  WorldSimulation sim(scenario);
  TrainWindowResult out;
  out.dt_s = sim.dt_s();
  out.session_path = o.record.empty() ? newSessionPath(o.record_dir, scenario.name) : o.record;
  SessionHeader header = sessionHeaderFor(scenario, o.colosim_version);
  header.mode = "interactive";
  SessionWriter writer(out.session_path, header);

  SharedRates rates;
  PhysicsLoop loop(sim, scenario.scoring, &writer,
                   operatorSource(scenario, sim.dt_s(), handleLimitsOf(sim.model().scope), rates, o.autopilot), {},
                   [](const std::string& m) { std::fprintf(stderr, "colosim train: warning: %s\n", m.c_str()); });

  {
    SceneView start_scene;
    sim.scene(start_scene);
    window.globalCamera() = globalCameraFor(start_scene, 640.0 / 480.0);
  }
  ViewKeys view(o.view);
  bool have_gamepad = false, said_gamepad = false;
  std::string gamepad_name;
  Snapshot snap;
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> frame_ms;
  ShownRates shown;
  shown.since = start;
  getloadavg(&out.load_average_1min, 1);
  const double cpu_start_s = processCpuSeconds();
  auto drawFrame = [&] {
    const int fb_w = window.framebufferWidth(), fb_h = window.framebufferHeight();
    if (!snap.has_scene || fb_w < 2 || fb_h < 1) return;  // minimised
    const int view_w = view.view() == "both" ? fb_w / 2 : fb_w;
    drawViews(renderer, snap.scene, view.view(), view_w, fb_h, window.globalCamera(), o.render_scale);
    drawOverlay(renderer, snap, scenario.scoring, shown.fps, shown.physics_hz, fb_w, fb_h);
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
      view.poll(w, have_gamepad);
      window.setGlobalViewLeft(view.view() == "both" ? 0.5 : view.view() == "global" ? 0.0 : 1.0);

      loop.latest(snap);
      drawFrame();
      window.swapBuffers();
      ++out.frames;
      const auto now = std::chrono::steady_clock::now();
      frame_ms.push_back(std::chrono::duration<double, std::milli>(now - frame_start).count());
      frame_start = now;
      shown.update(now, out.frames, snap.steps);
      if (o.quit_after_s >= 0 && std::chrono::duration<double>(now - start).count() >= o.quit_after_s) break;
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
  const double draw_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  loop.stop();
  const double cpu_s = processCpuSeconds() - cpu_start_s;
  out.loop = loop.finish();
  if (!o.screenshot.empty()) {
    loop.latest(snap);
    drawFrame();
    writePng(o.screenshot, window.read());
  }
  out.frames_per_s = draw_wall_s > 0 ? out.frames / draw_wall_s : 0.0;
  // Everything but the physics thread draws: the main thread and llvmpipe's rasterisers.
  out.draw_cpu_ms_per_frame = out.frames > 0 ? 1e3 * (cpu_s - out.loop.stats.cpu_s) / out.frames : 0.0;
  std::sort(frame_ms.begin(), frame_ms.end());
  out.frame_ms_median = frame_ms.empty() ? 0.0 : frame_ms[frame_ms.size() / 2];
  out.framebuffer_width_px = window.framebufferWidth();
  out.framebuffer_height_px = window.framebufferHeight();
  out.view = view.view();
  return out;
}

}  // namespace colosim
