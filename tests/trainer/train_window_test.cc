// The trainer window driven by a gamepad alone (issue 19: "keyboard and gamepad
// friendly"). A scripted pad goes through the same reader interface GLFW's joysticks do
// (TrainWindowOptions::gamepad): the d-pad and A choose and start a scenario on the start
// screen, the sticks drive the scope, Start pauses and resumes, B ends the session and
// quits from the score card. The recorded session must hold all of it and replay
// bit-identically. Run under xvfb-run by ctest (tests/CMakeLists.txt).
#include "trainer/train_window.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include <gtest/gtest.h>

#include "fixture.h"
#include "trainer/replay.h"
#include "trainer/session.h"
#include "trainer/world_simulation.h"

namespace colosim {
namespace {

// GLFW's gamepad layout (GamepadState).
enum Button { kA = 0, kB = 1, kStart = 7, kDpadUp = 11, kDpadRight = 12 };
enum Axis { kLeftY = 1, kRightY = 3 };

// A pad that goes through its steps in order. Each step is held for at least `frames`
// polls (the window polls once a frame), `seconds` of wall time and `sim_steps` physics
// steps of the session on screen, so that a slow frame or slow physics (sanitizers, a
// loaded machine) never swallows a press or shortens a push.
class ScriptedPad {
 public:
  struct Step {
    GamepadState state;
    int frames = 3;
    double seconds = 0.0;
    long sim_steps = 0;
  };
  void add(const GamepadState& state, int frames = 3, double seconds = 0.0, long sim_steps = 0) {
    steps_.push_back({state, frames, seconds, sim_steps});
  }
  /// The session's steps, once a frame (TrainWindowOptions::on_frame).
  void sawSteps(long steps) { steps_now_ = steps; }
  bool read(GamepadState* out, std::string* name) {
    if (name->empty()) *name = "scripted pad";
    const auto now = std::chrono::steady_clock::now();
    if (polls_ == 0) since_ = now, steps_since_ = steps_now_;
    ++polls_;
    if (k_ < steps_.size()) {
      const Step& s = steps_[k_];
      if (polls_ > s.frames && std::chrono::duration<double>(now - since_).count() >= s.seconds &&
          steps_now_ - steps_since_ >= s.sim_steps) {
        ++k_;
        polls_ = 1;
        since_ = now;
        steps_since_ = steps_now_;
      }
    }
    *out = k_ < steps_.size() ? steps_[k_].state : GamepadState{};
    return true;
  }
  /// The last step (the press that quits) was reached.
  bool reachedLastStep() const { return k_ + 1 >= steps_.size(); }

 private:
  std::vector<Step> steps_;
  size_t k_ = 0;
  int polls_ = 0;
  std::chrono::steady_clock::time_point since_;
  long steps_now_ = -1, steps_since_ = -1;  // the session's steps: last seen, at the step's start
};

GamepadState pressed(int button) {
  GamepadState s;
  s.buttons[button] = true;
  return s;
}

TEST(TrainWindow, AGamepadAloneChoosesDrivesPausesAndEnds) {
  test::TempDir dir;
  const GamepadState idle;
  GamepadState drive;
  drive.axes[kLeftY] = -1.0f;   // stick forward (GLFW: +y down): push
  drive.axes[kRightY] = -1.0f;  // right stick forward: tip up
  ScriptedPad pad;
  pad.add(idle, 3, 0.2);
  pad.add(pressed(kDpadUp));     // start screen: the scenario above (free_insertion)
  pad.add(idle);
  pad.add(pressed(kDpadRight));  // the next patient position
  pad.add(idle);
  pad.add(pressed(kA));          // start
  pad.add(idle, 3, 0.2);
  pad.add(drive, 3, 3.0, 1000);  // 3 s, and at least 1 s simulated however slow the physics
  pad.add(idle, 3, 0.3);
  pad.add(pressed(kStart));      // pause
  pad.add(idle, 3, 1.0);
  pad.add(pressed(kStart));      // go on
  pad.add(idle, 3, 0.2);
  pad.add(pressed(kB));          // end: the score card
  pad.add(idle);
  pad.add(pressed(kB));          // quit

  // Preselected: the second shipped scenario; the d-pad goes up to the first.
  const std::vector<std::string> names = shippedScenarioNames();
  ASSERT_GE(names.size(), 2u);
  const Scenario chosen = findScenario(names[0]);
  const std::vector<std::string>& positions = patientPositions();
  const size_t default_position =
      std::find(positions.begin(), positions.end(), patientPositionOf(chosen)) - positions.begin();
  const std::string want_position = positions[(default_position + 1) % positions.size()];

  TrainWindowOptions o;
  o.start_screen = true;
  o.width_px = 640;
  o.height_px = 360;
  o.record = dir.file("s.jsonl");
  o.quit_after_s = 120;  // a safety net: the pad quits long before
  o.colosim_version = "test";
  o.gamepad = [&pad](GamepadState* s, std::string* name) { return pad.read(s, name); };
  o.on_frame = [&pad](long steps) { pad.sawSteps(steps); };
  TrainWindowResult out;
  try {
    out = runTrainWindow(findScenario(names[1]), o);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find("GLFW") != std::string::npos) GTEST_SKIP() << "no display: " << e.what();
    throw;
  }

  EXPECT_TRUE(pad.reachedLastStep()) << "the window quit before the pad's last press";
  EXPECT_EQ(out.ended_by, "end");
  EXPECT_EQ(out.screens, (std::vector<std::string>{"start", "session", "score_card"}));
  ASSERT_EQ(out.sessions, std::vector<std::string>{o.record});
  EXPECT_EQ(out.scenario, names[0]);
  EXPECT_EQ(out.patient_position, want_position);

  const Session s = readSession(o.record);
  ASSERT_TRUE(s.complete) << s.message;
  EXPECT_EQ(s.header.scenario, chosen.id);
  EXPECT_EQ(s.header.patient_position, want_position);
  double first_insertion_m = s.inputs.front().input.insertion_m, max_insertion_m = first_insertion_m;
  double max_updown_rad = 0;
  for (const SessionInput& in : s.inputs) {
    max_insertion_m = std::max(max_insertion_m, in.input.insertion_m);
    max_updown_rad = std::max(max_updown_rad, in.input.knob_updown_rad);
  }
  // Full stick for 3 s and at least 1 s simulated: 9 cm and 4.5 rad when physics keeps up
  // with the wall clock, at least 3 cm and 1.5 rad when it does not; a tenth of that still
  // counts, none does not.
  EXPECT_GT(max_insertion_m - first_insertion_m, 0.009) << "the left stick did not push the scope";
  EXPECT_GT(max_updown_rad, 0.45) << "the right stick did not turn the up/down knob";
  std::vector<const SessionEvent*> pauses;
  for (const SessionEvent& e : s.events)
    if (e.name == "paused" || e.name == "resumed") pauses.push_back(&e);
  ASSERT_EQ(pauses.size(), 2u);
  EXPECT_EQ(pauses[0]->name, "paused");
  EXPECT_EQ(pauses[1]->name, "resumed");
  EXPECT_EQ(pauses[0]->step, pauses[1]->step) << "steps were taken while paused";

  // The card compares with free_insertion's expert session.
  ASSERT_TRUE(out.score_card.is_array());
  bool expert_shown = false;
  for (const auto& row : out.score_card)
    if (row["key"] == "peak_push_N") expert_shown = row["expert"].is_number();
  EXPECT_TRUE(expert_shown) << out.score_card.dump();

  const ReplayPlan plan = planReplay(o.record);
  WorldSimulation sim(plan.scenario);
  const ReplayResult r = replay(plan, sim);
  EXPECT_TRUE(r.final_hash_checked);
  EXPECT_TRUE(r.hashOk()) << r.mismatch;
}

}  // namespace
}  // namespace colosim
