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

#include <fcntl.h>
#include <imgui.h>
#include <unistd.h>

#include "core/colon_model.h"
#include "core/input_error.h"
#include "render/gui.h"
#include "render/image.h"
#include "render/renderer.h"
#include "render/window.h"
#include "trainer/expert_sessions.h"
#include "trainer/replay.h"
#include "trainer/scene_drawing.h"
#include "trainer/score_card.h"
#include "trainer/scope_inset.h"
#include "trainer/world_simulation.h"

namespace colosim {

const char* const kTrainKeyHelp =
    "Screens: the start screen (colosim train without SCENARIO, or --start-screen), the\n"
    "session, the score card at its end.\n"
    "Start screen: Up / Down (W / S) scenario, Left / Right (A / D) patient position,\n"
    "  Enter or Space start, Escape or Q quit.\n"
    "Session (keys held down; full speed 3 cm/s insertion, 1.5 rad/s rotation and knobs):\n"
    "  W / S  or  Up / Down      push / pull the scope\n"
    "  A / D  or  Left / Right   rotate anticlockwise / clockwise (seen by the operator)\n"
    "  I / K                     tip up / down (up/down knob)\n"
    "  J / L                     tip left / right (left/right knob)\n"
    "  Space                     both knobs back to neutral\n"
    "  Shift                     3x speed\n"
    "  1 / 2 / 3  (V cycles)     onboard / global / split view\n"
    "  mouse on the global view  left drag orbits, right drag pans, wheel zooms\n"
    "  P                         pause / go on (simulated time stands still)\n"
    "  R                         restart: end this session, start a new one\n"
    "  H                         call for abdominal pressure / release it (an assistant's hand)\n"
    "  T                         turn the patient: left lateral, supine, right lateral, prone\n"
    "  F                         next stiffness level of a variable-stiffness scope (cycles)\n"
    "  Escape                    end the session: the score card\n"
    "Score card: R restart, Enter or Space the start screen, Escape or Q quit.\n"
    "Gamepad (when GLFW finds one): left stick up/down push/pull, left stick left/right\n"
    "rotation, right stick the tip knobs, right bumper 3x speed, A centres the knobs, Back\n"
    "cycles the view, Start pauses, Y restarts, B ends, X abdominal pressure, left bumper\n"
    "turns the patient, pressing the right stick switches the stiffness level; on the screens the d-pad chooses, A\n"
    "or Start confirms, B goes back. Every session is recorded without being asked\n"
    "(--record-dir, --record).";

namespace {

// GamepadState's indices are GLFW's.
static_assert(GLFW_GAMEPAD_AXIS_LAST + 1 == std::tuple_size<decltype(GamepadState::axes)>::value);
static_assert(GLFW_GAMEPAD_BUTTON_LAST + 1 == std::tuple_size<decltype(GamepadState::buttons)>::value);

// The first joystick GLFW has a gamepad mapping for.
bool readGlfwGamepad(GamepadState* state, std::string* name) {
  for (int jid = GLFW_JOYSTICK_1; jid <= GLFW_JOYSTICK_LAST; ++jid) {
    GLFWgamepadstate pad;
    if (!glfwJoystickIsGamepad(jid) || !glfwGetGamepadState(jid, &pad)) continue;
    for (size_t k = 0; k < state->axes.size(); ++k) state->axes[k] = pad.axes[k];
    for (size_t k = 0; k < state->buttons.size(); ++k) state->buttons[k] = pad.buttons[k] == GLFW_PRESS;
    if (name->empty()) *name = glfwGetGamepadName(jid) ? glfwGetGamepadName(jid) : "gamepad";
    return true;
  }
  return false;
}

// Keyboard and gamepad (nullptr: none), polled once per frame.
ControlState pollControls(GLFWwindow* w, const GamepadState* pad) {
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
  if (pad) {
    // GLFW's sticks: +y is down.
    c.axis_insertion = -pad->axes[GLFW_GAMEPAD_AXIS_LEFT_Y];
    c.axis_rotation = pad->axes[GLFW_GAMEPAD_AXIS_LEFT_X];
    c.axis_updown = -pad->axes[GLFW_GAMEPAD_AXIS_RIGHT_Y];
    c.axis_leftright = pad->axes[GLFW_GAMEPAD_AXIS_RIGHT_X];
    c.fast = c.fast || pad->buttons[GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER];
    c.centre_knobs = c.centre_knobs || pad->buttons[GLFW_GAMEPAD_BUTTON_A];
  }
  return c;
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
  void poll(GLFWwindow* w, const GamepadState* pad) {
    const bool back = pad && pad->buttons[GLFW_GAMEPAD_BUTTON_BACK];
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


// The screens' one-shot actions (on the press, not while held), from keys and the gamepad.
enum Action { kUp, kDown, kLeft, kRight, kConfirm, kBack, kPause, kRestart, kQuit, kPressure, kTurn, kStiffness,
              kActionCount };

class ActionKeys {
 public:
  // Which actions were pressed since the last poll: keys from the window's press events
  // (never missed, even when pressed and released within a busy frame), gamepad buttons
  // on their press.
  std::array<bool, kActionCount> poll(const std::vector<int>& key_presses, const GamepadState* pad) {
    std::array<bool, kActionCount> pressed{};
    for (int k : key_presses) {
      if (k == GLFW_KEY_UP || k == GLFW_KEY_W) pressed[kUp] = true;
      if (k == GLFW_KEY_DOWN || k == GLFW_KEY_S) pressed[kDown] = true;
      if (k == GLFW_KEY_LEFT || k == GLFW_KEY_A) pressed[kLeft] = true;
      if (k == GLFW_KEY_RIGHT || k == GLFW_KEY_D) pressed[kRight] = true;
      if (k == GLFW_KEY_ENTER || k == GLFW_KEY_KP_ENTER || k == GLFW_KEY_SPACE) pressed[kConfirm] = true;
      if (k == GLFW_KEY_ESCAPE) pressed[kBack] = true;
      if (k == GLFW_KEY_P) pressed[kPause] = true;
      if (k == GLFW_KEY_R) pressed[kRestart] = true;
      if (k == GLFW_KEY_Q) pressed[kQuit] = true;
      if (k == GLFW_KEY_H) pressed[kPressure] = true;
      if (k == GLFW_KEY_T) pressed[kTurn] = true;
      if (k == GLFW_KEY_F) pressed[kStiffness] = true;
    }
    auto button = [&](int b) { return pad && pad->buttons[b]; };
    const std::array<bool, kActionCount> down{button(GLFW_GAMEPAD_BUTTON_DPAD_UP),
                                              button(GLFW_GAMEPAD_BUTTON_DPAD_DOWN),
                                              button(GLFW_GAMEPAD_BUTTON_DPAD_LEFT),
                                              button(GLFW_GAMEPAD_BUTTON_DPAD_RIGHT),
                                              button(GLFW_GAMEPAD_BUTTON_A),
                                              button(GLFW_GAMEPAD_BUTTON_B),
                                              button(GLFW_GAMEPAD_BUTTON_START),
                                              button(GLFW_GAMEPAD_BUTTON_Y),
                                              false,
                                              button(GLFW_GAMEPAD_BUTTON_X),
                                              button(GLFW_GAMEPAD_BUTTON_LEFT_BUMPER),
                                              button(GLFW_GAMEPAD_BUTTON_RIGHT_THUMB)};
    for (int a = 0; a < kActionCount; ++a) pressed[a] = pressed[a] || (down[a] && !pad_was_down_[a]);
    pad_was_down_ = down;
    return pressed;
  }

 private:
  // Down at the start counts as held: a button already down does nothing.
  std::array<bool, kActionCount> pad_was_down_{true, true, true, true, true, true, true, true, true, true, true, true};
};

// One recorded session: the simulation, its writer and the physics loop that steps it.
// Held on the heap and kept after the session ends, for the frozen view behind the card
// (the snapshot's scene points at the simulation's model).
struct ActiveSession {
  Scenario scenario;
  std::string path;
  std::unique_ptr<WorldSimulation> sim;
  std::unique_ptr<SessionWriter> writer;
  SharedRates rates;
  std::unique_ptr<PhysicsLoop> loop;
  CoronalFrame inset_frame;
  bool ended = false;
  PhysicsLoopResult result;
  std::string ended_by;
  AssistInput assist;  ///< what the trainee last asked for (H, T)
  int stiffness_level = -1;  ///< the variable-stiffness level the trainee chose (F); -1: the design's default
};

// The file of the n-th session (n from 1) when --record names one: the name itself, then
// NAME-2.jsonl, NAME-3.jsonl, ... created exclusively (never an existing file).
std::string recordPath(const std::string& record, int n) {
  if (n == 1) return record;
  // NAME-K.EXT, and NAME-K.EXT.gz for a compressed NAME.EXT.gz.
  bool compressed = false;
  const std::filesystem::path p(withoutGzipSuffix(record, &compressed));
  for (int k = n; k < n + 10000; ++k) {
    const std::string path =
        (p.parent_path() / (p.stem().string() + "-" + std::to_string(k) + p.extension().string())).string() +
        (compressed ? kGzipSuffix : "");
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd >= 0) {
      ::close(fd);
      return path;
    }
  }
  throw std::runtime_error(record + ": no free name for session " + std::to_string(n));
}

std::string positionLabel(const std::string& p) {
  if (p == "left_lateral") return "left lateral";
  if (p == "right_lateral") return "right lateral";
  return p;
}

ImVec4 bandColour(const std::string& band) {
  if (band == "green") return ImVec4(0.25f, 0.85f, 0.35f, 1.0f);
  if (band == "amber") return ImVec4(1.0f, 0.7f, 0.1f, 1.0f);
  if (band == "red") return ImVec4(1.0f, 0.3f, 0.25f, 1.0f);
  return ImVec4(0.6f, 0.6f, 0.6f, 1.0f);
}

const ImGuiWindowFlags kPanel = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove;

double radToDeg(double rad) { return rad * 180.0 / 3.14159265358979323846; }

// The live overlay: depth, handle force and torque, time, the handle's angles, the loop
// warning, pause, rates and keys.
void drawOverlay(const Snapshot& s, const ActiveSession& session, double fps, double physics_hz, bool paused,
                 float width_px, float height_px) {
  const Telemetry& t = s.telemetry;
  ImGui::SetNextWindowPos(ImVec2(8, 8));
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("overlay", nullptr, kPanel);
  ImGui::Text("%s", session.scenario.name.c_str());
  ImGui::Text("Depth   %.3f m", t.input.insertion_m);
  ImGui::Text("Force   %+.1f N", t.handle_force_N);
  ImGui::Text("Torque  %+.3f N m", t.handle_torque_Nm);
  ImGui::Text("Time    %.1f s", t.time_s);
  ImGui::TextColored(ImVec4(0.8f, 0.8f, 0.8f, 1.0f), "Rotation %+.0f deg  tip up %+.0f right %+.0f deg",
                     radToDeg(t.input.rotation_rad), radToDeg(t.input.knob_updown_rad),
                     radToDeg(t.input.knob_leftright_rad));
  if (std::abs(t.loop_turns) >= session.scenario.scoring.loop_turns)
    ImGui::TextColored(ImVec4(1.0f, 0.3f, 0.25f, 1.0f), "LOOP %.2f turns: pull back and torque", std::abs(t.loop_turns));
  if (paused) ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.2f, 1.0f), "PAUSED (P goes on)");
  if (!t.patient_position.empty())
    ImGui::TextColored(ImVec4(0.8f, 0.8f, 0.8f, 1.0f), "Patient %s%s%s", t.patient_position.c_str(),
                       t.patient_turning ? " (turning)" : "", t.abdominal_pressure ? "   abdominal pressure ON" : "");
  ImGui::End();

  ImGui::SetNextWindowPos(ImVec2(8, height_px - 8), 0, ImVec2(0, 1));
  ImGui::SetNextWindowBgAlpha(0.45f);
  ImGui::Begin("keys", nullptr, kPanel);
  ImGui::TextColored(ImVec4(0.8f, 0.8f, 0.8f, 1.0f),
                     "physics %.0f/s  draw %.0f fps   W/S push/pull  A/D rotate  I/K J/L tip  Space centre tip  "
                     "Shift fast  1 2 3 view  H pressure  T turn  P pause  R restart  Esc end",
                     physics_hz, fps);
  ImGui::End();
  (void)width_px;
}

// The scope-shape inset: the scope's centreline seen from the front of the patient.
void drawScopeInset(const Snapshot& s, const ActiveSession& session, float width_px, float height_px) {
  const float side = std::min(200.0f, 0.35f * height_px);
  ImGui::SetNextWindowPos(ImVec2(width_px - 8, 8), 0, ImVec2(1, 0));
  ImGui::SetNextWindowBgAlpha(0.75f);
  ImGui::Begin("inset", nullptr, kPanel);
  ImGui::TextColored(ImVec4(0.8f, 0.8f, 0.8f, 1.0f), "Scope shape (coronal, from the front)");
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("inset_area", ImVec2(side, side));
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(origin, ImVec2(origin.x + side, origin.y + side), IM_COL32(10, 14, 24, 255));
  dl->PushClipRect(origin, ImVec2(origin.x + side, origin.y + side), true);
  if (s.has_scene && s.scene.scope_centreline_m.size() >= 2) {
    const std::vector<std::array<float, 2>> pts = coronalInset(s.scene.scope_centreline_m, session.inset_frame, side, side);
    std::vector<ImVec2> line;
    line.reserve(pts.size());
    for (const auto& p : pts) line.emplace_back(origin.x + p[0], origin.y + p[1]);
    dl->AddPolyline(line.data(), static_cast<int>(line.size()), IM_COL32(60, 230, 110, 255), 0, 3.0f);
    dl->AddCircleFilled(line.back(), 4.5f, IM_COL32(255, 215, 30, 255));
  }
  dl->PopClipRect();
  ImGui::TextColored(ImVec4(0.6f, 0.6f, 0.6f, 1.0f), "patient's right  |  left; head up");
  ImGui::End();
}

// The start screen: scenarios, patient positions, the goal and the keys.
// A click on a scenario selects it (returned through clicked_scenario, -1: none).
void drawStartScreen(const std::vector<Scenario>& scenarios, int selected, const std::vector<std::string>& positions,
                     int position, float width_px, float height_px, bool* start_clicked, int* clicked_scenario) {
  ImGui::SetNextWindowPos(ImVec2(0.5f * width_px, 0.5f * height_px), 0, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(std::min(width_px - 20, 980.0f), std::min(height_px - 20, 640.0f)));
  ImGui::Begin("colosim train: choose a scenario", nullptr,
               ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoNav |
                   ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
  ImGui::Columns(2, "start", true);
  ImGui::SetColumnWidth(0, 300);
  ImGui::TextColored(ImVec4(0.7f, 0.8f, 1.0f, 1.0f), "Scenario  (Up / Down)");
  *clicked_scenario = -1;
  for (size_t k = 0; k < scenarios.size(); ++k)
    if (ImGui::Selectable(scenarios[k].name.c_str(), static_cast<int>(k) == selected))
      *clicked_scenario = static_cast<int>(k);
  ImGui::Spacing();
  ImGui::TextColored(ImVec4(0.7f, 0.8f, 1.0f, 1.0f), "Patient position  (Left / Right)");
  ImGui::Text("< %s >", positionLabel(positions[position]).c_str());
  ImGui::Spacing();
  *start_clicked = ImGui::Button("Start  (Enter)");
  ImGui::NextColumn();
  const Scenario& sc = scenarios[selected];
  ImGui::TextColored(ImVec4(0.7f, 0.8f, 1.0f, 1.0f), "Goal");
  ImGui::TextWrapped("%s", (sc.goal.empty() ? sc.description : sc.goal).c_str());
  ImGui::Spacing();
  ImGui::TextColored(ImVec4(0.7f, 0.8f, 1.0f, 1.0f), "Keys");
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextUnformatted(kTrainKeyHelp);
  ImGui::PopTextWrapPos();
  ImGui::Columns(1);
  ImGui::End();
}

// The score card: each metric with its unit, the expert's value and the band.
void drawScoreCard(const ActiveSession& session, const std::vector<ScoreCardRow>& rows, bool have_expert,
                   float width_px, float height_px) {
  ImGui::SetNextWindowPos(ImVec2(0.5f * width_px, 0.5f * height_px), 0, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(std::min(width_px - 20, 900.0f), std::min(height_px - 20, 600.0f)));
  ImGui::SetNextWindowBgAlpha(0.92f);
  const std::string title = "Score card: " + session.scenario.name + " (" +
                            positionLabel(patientPositionOf(session.scenario)) + ")###score_card";
  ImGui::Begin(title.c_str(), nullptr,
               ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoNav |
                   ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
  ImGui::Text("%.1f s simulated, session %s", session.result.steps * session.sim->dt_s(), session.path.c_str());
  if (!have_expert) ImGui::TextColored(bandColour("none"), "No expert reference for this scenario: no relative bands.");
  if (ImGui::BeginTable("card", 4, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
    ImGui::TableSetupColumn("Metric", ImGuiTableColumnFlags_WidthStretch, 2.2f);
    ImGui::TableSetupColumn("You", ImGuiTableColumnFlags_WidthStretch, 1.2f);
    ImGui::TableSetupColumn("Expert", ImGuiTableColumnFlags_WidthStretch, 1.2f);
    ImGui::TableSetupColumn("Band", ImGuiTableColumnFlags_WidthStretch, 0.6f);
    ImGui::TableHeadersRow();
    for (const ScoreCardRow& r : rows) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(r.label.c_str());
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", r.rule.c_str());
      const std::string unit = r.unit.empty() ? "" : " " + r.unit;
      ImGui::TableNextColumn();
      ImGui::Text("%s%s", formatCardValue(r.key, r.value).c_str(), r.value ? unit.c_str() : "");
      ImGui::TableNextColumn();
      ImGui::Text("%s%s", formatCardValue(r.key, r.expert).c_str(), r.expert ? unit.c_str() : "");
      ImGui::TableNextColumn();
      ImGui::TextColored(bandColour(r.band), "%s", r.band == "none" ? "-" : r.band.c_str());
    }
    ImGui::EndTable();
  }
  ImGui::TextColored(ImVec4(0.7f, 0.7f, 0.7f, 1.0f),
                     "Bands: time to caecum against clinical thresholds, the others relative to the expert's\n"
                     "scripted run (hover a metric for its rule; docs/trainer-window.md).   R restart   "
                     "Enter start screen   Esc/Q quit");
  ImGui::End();
}

}  // namespace

TrainWindowResult runTrainWindow(const Scenario& first_scenario, const TrainWindowOptions& o) {
  // Every input is checked before a window or a file is opened.
  if (!o.screenshot.empty() && std::filesystem::exists(o.screenshot))
    throw InputError(o.screenshot + ": exists (a screenshot never overwrites a file)");
  if (!o.record.empty() && std::filesystem::exists(o.record))
    throw InputError(o.record + ": exists (a session never overwrites a file); choose a new name or --record-dir");
  // The score card's references: the expert sessions' headers and end lines.
  const std::vector<ExpertSession> experts = loadExpertSessions();
  // The start screen's list: the given scenario first when it is not a shipped one.
  std::vector<Scenario> scenarios;
  int selected = 0;
  if (o.start_screen) {
    for (const std::string& name : shippedScenarioNames()) scenarios.push_back(findScenario(name));
    auto it = std::find_if(scenarios.begin(), scenarios.end(),
                           [&](const Scenario& s) { return s.file_hash == first_scenario.file_hash && s.name == first_scenario.name; });
    if (it == scenarios.end()) scenarios.insert(scenarios.begin(), first_scenario);
    else selected = static_cast<int>(it - scenarios.begin());
  } else {
    scenarios.push_back(first_scenario);
  }
  const std::vector<std::string>& positions = patientPositions();
  auto positionIndexOf = [&](const Scenario& sc) {
    const std::string p = patientPositionOf(sc);
    return static_cast<int>(std::find(positions.begin(), positions.end(), p) - positions.begin()) %
           static_cast<int>(positions.size());
  };
  int position = positionIndexOf(scenarios[selected]);
  setRenderThreads(o.render_threads);

  Window window(o.width_px, o.height_px, "colosim train " + first_scenario.name);
  Renderer renderer;
  Gui gui(window);
  TrainWindowResult out;

  enum class Screen { kStart, kSession, kScoreCard };
  Screen screen = o.start_screen ? Screen::kStart : Screen::kSession;
  std::unique_ptr<ActiveSession> session;
  std::vector<ScoreCardRow> card;
  const ExpertSession* card_expert = nullptr;
  int session_count = 0;

  auto warn = [](const std::string& m) { std::fprintf(stderr, "colosim train: warning: %s\n", m.c_str()); };
  // Starts a new recorded session of `sc` (the physics loop on its own thread).
  auto startSession = [&](Scenario sc) {
    auto a = std::make_unique<ActiveSession>();
    a->scenario = std::move(sc);
    a->sim = std::make_unique<WorldSimulation>(a->scenario);
    ++session_count;
    a->path = o.record.empty() ? newSessionPath(o.record_dir, a->scenario.name) : recordPath(o.record, session_count);
    SessionHeader header = sessionHeaderFor(a->scenario, o.colosim_version);
    header.mode = "interactive";
    a->writer = std::make_unique<SessionWriter>(a->path, header);
    a->loop = std::make_unique<PhysicsLoop>(
        *a->sim, a->scenario.scoring, a->writer.get(),
        operatorSource(a->scenario, a->sim->dt_s(), handleLimitsOf(a->sim->model().scope), a->rates, o.autopilot),
        PhysicsLoopOptions{}, warn);
    SceneView start_scene;
    a->sim->scene(start_scene);
    window.globalCamera() = globalCameraFor(start_scene, 640.0 / 480.0);
    a->inset_frame = coronalFrameFor(start_scene.colon->q_rest, 1.0);
    glfwSetWindowTitle(window.handle(), ("colosim train " + a->scenario.name).c_str());
    out.sessions.push_back(a->path);
    out.screens.push_back("session");
    a->loop->start();
    session = std::move(a);
  };
  // Ends the running session: the end line with the scores, and what the summary keeps.
  auto endSession = [&](const std::string& ended_by) {
    if (!session || session->ended) return;
    session->loop->stop();
    session->ended = true;
    session->ended_by = ended_by;
    session->result = session->loop->finish(ended_by);
    out.session_path = session->path;
    out.scenario = session->scenario.name;
    out.patient_position = patientPositionOf(session->scenario);
    out.ended_by = ended_by;
    out.loop = session->result;
    out.dt_s = session->sim->dt_s();
  };
  auto showCard = [&] {
    // The references are for the shipped scenarios only (a scenario file of the same name
    // elsewhere may differ): a shipped scenario's id is its name.
    const Scenario& sc = session->scenario;
    card_expert = sc.id == sc.name ? expertFor(sc, experts) : nullptr;
    card = scoreCard(session->result.scores, card_expert ? &card_expert->scores : nullptr);
    out.score_card = scoreCardJson(card);
    out.screens.push_back("score_card");
    screen = Screen::kScoreCard;
  };
  auto chosenScenario = [&] {
    Scenario sc = scenarios[selected];
    choosePatientPosition(sc, positions[position]);
    return sc;
  };

  ViewKeys view(o.view);
  ActionKeys actions;
  bool said_gamepad = false;
  std::string gamepad_name;
  Snapshot snap;
  const auto start = std::chrono::steady_clock::now();
  auto first_shown = start;  // when the first frame was shown (set in the loop)
  std::vector<double> frame_ms;
  ShownRates shown;
  shown.since = start;
  getloadavg(&out.load_average_1min, 1);
  const double cpu_start_s = processCpuSeconds();
  double physics_cpu_s = 0;  // of the sessions that ended
  // One frame of the current screen, ImGui over the views.
  auto drawFrame = [&](bool* start_clicked) {
    const int fb_w = window.framebufferWidth(), fb_h = window.framebufferHeight();
    if (fb_w < 2 || fb_h < 1) return;  // minimised
    if (screen != Screen::kStart && session && snap.has_scene) {
      const int view_w = view.view() == "both" ? fb_w / 2 : fb_w;
      drawViews(renderer, snap.scene, view.view(), view_w, fb_h, window.globalCamera(), o.render_scale);
    } else {
      window.clear(0.07f, 0.08f, 0.11f);
    }
    gui.newFrame();
    int win_w = 0, win_h = 0;
    glfwGetWindowSize(window.handle(), &win_w, &win_h);
    const float w = static_cast<float>(win_w), h = static_cast<float>(win_h);
    if (screen == Screen::kStart) {
      int clicked = -1;
      drawStartScreen(scenarios, selected, positions, position, w, h, start_clicked, &clicked);
      if (clicked >= 0 && clicked != selected) {
        selected = clicked;
        position = positionIndexOf(scenarios[selected]);
      }
    } else if (session) {
      drawOverlay(snap, *session, shown.fps, shown.physics_hz, session->loop->paused(), w, h);
      drawScopeInset(snap, *session, w, h);
      if (screen == Screen::kScoreCard) drawScoreCard(*session, card, card_expert != nullptr, w, h);
    }
    gui.render();
  };

  if (screen == Screen::kStart) out.screens.push_back("start");
  else startSession(first_scenario);
  std::string quit_reason = "close";
  try {
    auto frame_start = std::chrono::steady_clock::now();
    bool quit = false;
    while (!quit) {
      window.pollEvents();
      if (window.shouldClose()) break;
      GLFWwindow* w = window.handle();
      GamepadState pad_state;
      const bool have_gamepad =
          o.gamepad ? o.gamepad(&pad_state, &gamepad_name) : readGlfwGamepad(&pad_state, &gamepad_name);
      const GamepadState* pad = have_gamepad ? &pad_state : nullptr;
      if (have_gamepad && !said_gamepad) {
        std::fprintf(stderr, "colosim train: gamepad: %s\n", gamepad_name.c_str());
        said_gamepad = true;
      }
      const std::array<bool, kActionCount> pressed = actions.poll(window.takeKeyPresses(), pad);
      window.setMouseBlocked(gui.wantsMouse());
      const ControlState controls = pollControls(w, pad);
      view.poll(w, pad);
      window.setGlobalViewLeft(view.view() == "both" ? 0.5 : view.view() == "global" ? 0.0 : 1.0);

      // The screen's actions.
      if (screen == Screen::kStart) {
        const int n = static_cast<int>(scenarios.size()), m = static_cast<int>(positions.size());
        if (pressed[kUp]) selected = (selected + n - 1) % n;
        if (pressed[kDown]) selected = (selected + 1) % n;
        if (pressed[kUp] || pressed[kDown]) position = positionIndexOf(scenarios[selected]);
        if (pressed[kLeft]) position = (position + m - 1) % m;
        if (pressed[kRight]) position = (position + 1) % m;
        if (pressed[kBack] || pressed[kQuit]) break;
        if (pressed[kConfirm] || pressed[kPause]) {
          session.reset();
          snap = Snapshot();
          startSession(chosenScenario());
          screen = Screen::kSession;
        }
      } else if (screen == Screen::kSession) {
        if (pressed[kStiffness])  // a scope without a variable-stiffness section ignores the key
          session->stiffness_level = nextStiffnessLevel(session->sim->model().scope, session->stiffness_level);
        HandleRates rates = ratesFromControls(controls);
        rates.stiffness_level = session->stiffness_level;
        session->rates.set(rates);
        if (pressed[kPause]) session->loop->setPaused(!session->loop->paused());
        if (pressed[kPressure] || pressed[kTurn]) {
          // The assistance goes into the session as an assist line at the next step.
          AssistInput& a = session->assist;
          if (a.patient_position.empty())  // the position the session started in
            a.patient_position = snap.telemetry.patient_position.empty() ? patientPositionOf(session->scenario)
                                                                         : snap.telemetry.patient_position;
          if (pressed[kPressure]) a.abdominal_pressure = !a.abdominal_pressure;
          if (pressed[kTurn]) a.patient_position = nextPatientPosition(a.patient_position);
          session->loop->requestAssist(a);
        }
        if (pressed[kRestart]) {
          endSession("restart");
          Scenario again = session->scenario;
          physics_cpu_s += session->result.stats.cpu_s;
          session.reset();
          snap = Snapshot();
          startSession(again);
        } else if (pressed[kBack]) {
          endSession("end");
          physics_cpu_s += session->result.stats.cpu_s;
          showCard();
        } else if (!session->loop->running()) {
          break;  // the loop stopped by itself: only on an error (finish rethrows it)
        }
      } else {  // score card
        if (pressed[kBack] || pressed[kQuit]) break;
        if (pressed[kRestart]) {
          Scenario again = session->scenario;
          session.reset();
          snap = Snapshot();
          startSession(again);
          screen = Screen::kSession;
        } else if (pressed[kConfirm]) {
          screen = Screen::kStart;
          out.screens.push_back("start");
        }
      }

      if (session) session->loop->latest(snap);
      if (o.on_frame) o.on_frame(session ? snap.steps : -1);
      bool start_clicked = false;
      drawFrame(&start_clicked);
      if (start_clicked && screen == Screen::kStart) {
        session.reset();
        snap = Snapshot();
        startSession(chosenScenario());
        screen = Screen::kSession;
      }
      const auto now = std::chrono::steady_clock::now();
      // --quit-after counts from the first frame shown: start-up (the first frame's shader
      // compilation, seconds under the sanitizers on a loaded machine) is not session time.
      if (out.frames == 0) first_shown = now;
      if (o.quit_after_s >= 0 && std::chrono::duration<double>(now - first_shown).count() >= o.quit_after_s) {
        quit = true;
        quit_reason = "quit_after";
      }
      // The last frame is read before it is shown (the back buffer is undefined after).
      if (quit && !o.screenshot.empty()) writePng(o.screenshot, window.read());
      window.swapBuffers();
      ++out.frames;
      frame_ms.push_back(std::chrono::duration<double, std::milli>(now - frame_start).count());
      frame_start = now;
      shown.update(now, out.frames, snap.steps);
    }
    if (!quit && !o.screenshot.empty()) {
      bool ignored = false;
      drawFrame(&ignored);
      writePng(o.screenshot, window.read());
    }
  } catch (...) {
    // Close the session properly (end line) before reporting the error.
    if (session && !session->ended) {
      session->loop->stop();
      try {
        session->loop->finish("error");
      } catch (...) {  // the draw error is the one to report
      }
    }
    throw;
  }
  const double draw_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (session && !session->ended) {
    endSession(quit_reason);
    physics_cpu_s += session->result.stats.cpu_s;
  }
  const double cpu_s = processCpuSeconds() - cpu_start_s;
  out.frames_per_s = draw_wall_s > 0 ? out.frames / draw_wall_s : 0.0;
  // Everything but the physics threads draws: the main thread and llvmpipe's rasterisers.
  out.draw_cpu_ms_per_frame = out.frames > 0 ? 1e3 * (cpu_s - physics_cpu_s) / out.frames : 0.0;
  std::sort(frame_ms.begin(), frame_ms.end());
  out.frame_ms_median = frame_ms.empty() ? 0.0 : frame_ms[frame_ms.size() / 2];
  out.framebuffer_width_px = window.framebufferWidth();
  out.framebuffer_height_px = window.framebufferHeight();
  out.view = view.view();
  return out;
}

}  // namespace colosim
