// The trainee's calls for help: an assistant's abdominal pressure and the patient turned
// (AssistInput): recorded as session assist lines, replayed bit-identically, and doing what
// they say to the physics (gravity turned about the body's long axis, the pressed colon held).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "fixture.h"
#include "session_fixture.h"
#include "trainer/interactive.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/session.h"
#include "trainer/world_simulation.h"
#include "core/numbers.h"

namespace colosim {
namespace {

AssistInput assistOf(bool pressure, const std::string& position) {
  AssistInput a;
  a.abdominal_pressure = pressure;
  a.patient_position = position;
  return a;
}

TEST(Assist, SessionAssistLinesRoundTripAndBadOnesAreRefused) {
  test::TempDir dir;
  const std::string path = dir.file("assist.jsonl");
  {
    SessionHeader h;
    h.scenario = "small";
    h.dt_s = 0.01;
    SessionWriter w(path, h);
    w.input(0, HandleInput());
    w.assist(3, assistOf(true, "left_lateral"));
    w.assist(5, assistOf(true, "left_lateral"));  // unchanged: not written
    w.assist(7, assistOf(false, "supine"));
    w.end(10, 42, nlohmann::json::object());
  }
  const Session s = readSession(path);
  ASSERT_EQ(s.assists.size(), 2u);
  EXPECT_EQ(s.assists[0].step, 3);
  EXPECT_TRUE(s.assists[0].assist.abdominal_pressure);
  EXPECT_EQ(s.assists[0].assist.patient_position, "left_lateral");
  EXPECT_EQ(s.assists[1].step, 7);
  EXPECT_FALSE(s.assists[1].assist.abdominal_pressure);
  EXPECT_EQ(s.assists[1].assist.patient_position, "supine");

  const std::string head =
      R"({"type":"header","format":"colosim-session","version":1,"scenario":"small","scenario_hash":"0000000000000000",)"
      R"("params_hash":"0000000000000000","anatomy_hash":"0000000000000000","colosim_version":"t","dt_s":0.01,"seed":0,)"
      R"("mode":"interactive"})" "\n"
      R"({"type":"input","step":0,"t_s":0,"insertion_m":0,"rotation_rad":0,"knob_updown_rad":0,"knob_leftright_rad":0})" "\n";
  test::expectInputError(
      [&] {
        parseSession(head + R"({"type":"assist","step":2,"t_s":0.02,"abdominal_pressure":true,"patient_position":"upside_down"})" "\n",
                     "bad.jsonl");
      },
      {"bad.jsonl:3", "patient_position", "upside_down"});
  test::expectInputError(
      [&] {
        parseSession(head + R"({"type":"assist","step":2,"t_s":0.02,"abdominal_pressure":true,"patient_position":"supine"})" "\n" +
                         R"({"type":"assist","step":2,"t_s":0.02,"abdominal_pressure":false,"patient_position":"supine"})" "\n",
                     "twice.jsonl");
      },
      {"twice.jsonl:4", "step"});
  test::expectInputError(
      [&] {
        parseSession(head + R"({"type":"assist","step":2,"t_s":0.02,"patient_position":"supine"})" "\n", "short.jsonl");
      },
      {"short.jsonl:3", "abdominal_pressure"});
}

TEST(Assist, NextPositionIsAQuarterTurn) {
  EXPECT_EQ(nextPatientPosition("left_lateral"), "supine");
  EXPECT_EQ(nextPatientPosition("supine"), "right_lateral");
  EXPECT_EQ(nextPatientPosition("right_lateral"), "prone");
  EXPECT_EQ(nextPatientPosition("prone"), "left_lateral");
  EXPECT_THROW(nextPatientPosition("sitting"), InputError);
}

// Steps `sim` for `seconds` with the scope outside.
void idle(WorldSimulation& sim, double seconds) {
  const long n = std::lround(seconds / sim.dt_s());
  for (long k = 0; k < n; ++k) sim.step(HandleInput());
}

TEST(Assist, TurningThePatientRotatesGravityAboutTheLongAxis) {
  const Scenario sc = findScenario("free_insertion");  // left lateral
  WorldSimulation sim(sc);
  const double g = sim.model().colon.gravity_m_per_s2.norm();
  ASSERT_EQ(sim.telemetry().patient_position, "left_lateral");
  EXPECT_NEAR(sim.model().colon.gravity_m_per_s2.x(), g, 1e-12);
  // A quarter turn onto the back: gravity goes from the patient's left to posterior.
  sim.assist(assistOf(false, "supine"));
  idle(sim, 0.5 * WorldSimulation::kTurnDuration_s);
  EXPECT_TRUE(sim.telemetry().patient_turning);
  EXPECT_EQ(sim.telemetry().patient_position, "supine");
  const Vec3 mid = sim.model().colon.gravity_m_per_s2;
  EXPECT_NEAR(mid.norm(), g, 1e-9);
  EXPECT_NEAR(std::atan2(mid.y(), mid.x()), kPi / 4, 0.01) << "half way in time, half way in angle";
  EXPECT_EQ(mid.z(), 0.0) << "about the long axis";
  EXPECT_EQ(sim.model().scope.gravity_m_per_s2, mid) << "the scope feels the same gravity";
  idle(sim, 0.5 * WorldSimulation::kTurnDuration_s + 0.01);
  EXPECT_FALSE(sim.telemetry().patient_turning);
  EXPECT_NEAR((sim.model().colon.gravity_m_per_s2 - Vec3(0, g, 0)).norm(), 0.0, 1e-12);
  // Right lateral, then back to left lateral: half a turn, rolled over the back.
  sim.assist(assistOf(false, "right_lateral"));
  idle(sim, WorldSimulation::kTurnDuration_s + 0.01);
  EXPECT_NEAR((sim.model().colon.gravity_m_per_s2 - Vec3(-g, 0, 0)).norm(), 0.0, 1e-12);
  sim.assist(assistOf(false, "left_lateral"));
  idle(sim, 0.5 * WorldSimulation::kTurnDuration_s);
  EXPECT_GT(sim.model().colon.gravity_m_per_s2.y(), 0.99 * g) << "supine half way";
  idle(sim, 0.5 * WorldSimulation::kTurnDuration_s + 0.01);
  EXPECT_NEAR((sim.model().colon.gravity_m_per_s2 - Vec3(g, 0, 0)).norm(), 0.0, 1e-12);
  // Supine to prone: half a turn over the patient's left side.
  sim.assist(assistOf(false, "supine"));
  idle(sim, WorldSimulation::kTurnDuration_s + 0.01);
  sim.assist(assistOf(false, "prone"));
  idle(sim, 0.5 * WorldSimulation::kTurnDuration_s);
  EXPECT_GT(sim.model().colon.gravity_m_per_s2.x(), 0.99 * g) << "left lateral half way";
  idle(sim, 0.5 * WorldSimulation::kTurnDuration_s + 0.01);
  EXPECT_NEAR((sim.model().colon.gravity_m_per_s2 - Vec3(0, -g, 0)).norm(), 0.0, 1e-12);
  EXPECT_THROW(sim.assist(assistOf(false, "standing")), InputError);
}

// A scenario's patient_turns turn the patient as a trainee's call does: a run with a turn
// to supine at 0.2 s is bit-identical to one whose trainee asks for it before the step
// starting at 0.2 s, and gravity ends posterior (the patient on the back) after the turn.
TEST(Assist, AScenariosPatientTurnIsATraineesCallAtItsTime) {
  Scenario scripted = findScenario("free_insertion");  // left lateral
  scripted.patient_turns = {{0.2, "supine"}};
  Scenario called = findScenario("free_insertion");
  WorldSimulation a(scripted), b(called);
  const double g = a.model().colon.gravity_m_per_s2.norm();
  const long turn_step = std::lround(0.2 / a.dt_s());
  const long steps = std::lround((0.2 + WorldSimulation::kTurnDuration_s + 0.1) / a.dt_s());
  for (long k = 0; k < steps; ++k) {
    const HandleInput in = scriptedInput(called.script, static_cast<double>(k) * a.dt_s());
    if (k == turn_step) b.assist(assistOf(false, "supine"));
    a.step(in);
    b.step(in);
    if (k == turn_step - 1) {
      EXPECT_NEAR((a.model().colon.gravity_m_per_s2 - Vec3(g, 0, 0)).norm(), 0.0, 1e-12) << "not turned before its time";
    }
  }
  EXPECT_EQ(a.stateHash(), b.stateHash());
  EXPECT_EQ(a.telemetry().patient_position, "supine");
  EXPECT_FALSE(a.telemetry().patient_turning);
  EXPECT_NEAR((a.model().colon.gravity_m_per_s2 - Vec3(0, g, 0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(a.model().colon.gravity_m_per_s2, b.model().colon.gravity_m_per_s2);
  // Restarted, the run turns again at its time: the same state.
  WorldSimulation c(scripted);
  for (long k = 0; k < steps; ++k) c.step(scriptedInput(called.script, static_cast<double>(k) * c.dt_s()));
  EXPECT_EQ(c.stateHash(), a.stateHash());
}

// The largest displacement of the sigmoid's control points from `from` [m].
double sigmoidMoved(const WorldSimulation& sim, const Points& from) {
  const ColonModel& c = sim.model().colon;
  double most = 0;
  for (int j = 0; j + 1 < c.n; ++j)
    if (c.region_names[c.segment_region[j]] == "sigmoid")
      most = std::max(most, (sim.state().colon.q.col(j) - from.col(j)).norm());
  return most;
}

TEST(Assist, AbdominalPressureHoldsTheSigmoidWhileThePatientIsTurned) {
  // free_insertion's assistant presses the sigmoid among other regions. Turned from the left
  // side onto the back, the mobile sigmoid falls several centimetres; pressed, far less.
  const Scenario sc = findScenario("free_insertion");
  double moved_m[2];
  for (int pressed = 0; pressed < 2; ++pressed) {
    WorldSimulation sim(sc);
    if (pressed) {
      sim.assist(assistOf(true, "left_lateral"));
      idle(sim, 1.0);  // the ramp in
    }
    const Points from = sim.state().colon.q;
    sim.assist(assistOf(pressed == 1, "supine"));
    idle(sim, WorldSimulation::kTurnDuration_s + 1.0);
    moved_m[pressed] = sigmoidMoved(sim, from);
    if (pressed) {  // letting go: the hand's lifters ramp out within a second
      sim.assist(assistOf(false, "supine"));
      idle(sim, 1.01);
      for (const RegionSupport& r : sim.state().support) EXPECT_EQ(r.stiffness_N_per_m2, 0.0);
    }
  }
  std::printf("sigmoid moved %.4f m free, %.4f m pressed\n", moved_m[0], moved_m[1]);
  EXPECT_GT(moved_m[0], 0.02) << "the free sigmoid falls when the patient turns";
  EXPECT_LT(moved_m[1], 0.5 * moved_m[0]) << "held by the assistant's hand";
}

TEST(Assist, AnInteractiveSessionWithAssistanceReplaysBitIdentically) {
  test::TempDir dir;
  const Scenario sc = findScenario("free_insertion");
  const std::string path = dir.file("assisted.jsonl");
  PhysicsLoopResult recorded;
  {
    WorldSimulation sim(sc);
    SessionHeader header = sessionHeaderFor(sc, "test");
    header.mode = "interactive";
    SessionWriter writer(path, header);
    PhysicsLoop* loop_ptr = nullptr;
    // Asked for from the physics thread's input source: applied at the next boundary.
    InputSource source = [&](long step, const HandleInput& prev) {
      if (step == 100) loop_ptr->requestAssist(assistOf(true, "supine"));
      if (step == 900) loop_ptr->requestAssist(assistOf(false, "supine"));
      HandleInput in = prev;
      in.insertion_m = 0.03 * step * sc.dt_s;  // 3 cm/s
      return in;
    };
    PhysicsLoopOptions opt;
    opt.real_time = false;
    // The state hash checkpoint at step 1000 (one a simulated second) follows both
    // requests, the end 100 steps later (1500 steps before: 39 s under the sanitizers).
    opt.max_steps = 1100;
    PhysicsLoop loop(sim, sc.scoring, &writer, source, opt);
    loop_ptr = &loop;
    loop.run();
    recorded = loop.finish();
  }
  const ReplayPlan plan = planReplay(path);
  ASSERT_EQ(plan.session.assists.size(), 2u);
  EXPECT_EQ(plan.session.assists[0].step, 101);
  EXPECT_EQ(plan.session.assists[1].step, 901);
  ASSERT_EQ(plan.session.checkpoints.size(), 1u);
  EXPECT_EQ(plan.session.checkpoints[0].step, 1000);
  WorldSimulation again(plan.scenario);
  const ReplayResult r = replay(plan, again);
  EXPECT_TRUE(r.hashOk()) << r.mismatch;
  EXPECT_TRUE(r.final_hash_checked);
  EXPECT_EQ(r.final_state_hash, recorded.final_state_hash);
  // Without the assistance the same inputs end elsewhere: the lines matter.
  Session bare = plan.session;
  bare.assists.clear();
  ReplayPlan bare_plan = plan;
  bare_plan.session = bare;
  WorldSimulation alone(plan.scenario);
  EXPECT_NE(replay(bare_plan, alone).final_state_hash, recorded.final_state_hash);
}

}  // namespace
}  // namespace colosim
