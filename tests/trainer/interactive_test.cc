// The interactive trainer's library (trainer/interactive.h), driven headless: controls to
// handle inputs, the physics loop's recording replayed bit-identically (scripted and with
// the controls changed from another thread while it runs), real-time pacing, dropping
// time when behind, snapshots and session file names.
#include "trainer/interactive.h"

#include <atomic>
#include <cmath>
#include <filesystem>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "fake_simulation.h"
#include "fixture.h"
#include "session_fixture.h"
#include "trainer/replay.h"
#include "trainer/world_simulation.h"
#include "core/numbers.h"

namespace colosim {
namespace {

TEST(IntegrateHandle, ClampsEveryInputToItsRange) {
  HandleLimits lim;
  lim.insertion_max_m = 1.5;
  HandleRates r;
  r.insertion_m_per_s = -0.1;
  HandleInput in;
  in = integrateHandle(in, r, 0.001, lim);
  EXPECT_EQ(in.insertion_m, 0.0);  // cannot pull out further than the anus
  in.insertion_m = 1.4999;
  r.insertion_m_per_s = 1.0;
  in = integrateHandle(in, r, 0.001, lim);
  EXPECT_EQ(in.insertion_m, 1.5);
  in = integrateHandle(in, r, 0.001, lim);
  EXPECT_EQ(in.insertion_m, 1.5);
  // Knobs stop at their stops and come back from them at once.
  r = HandleRates();
  r.knob_updown_rad_per_s = 10.0;
  r.knob_leftright_rad_per_s = -10.0;
  for (int k = 0; k < 1000; ++k) in = integrateHandle(in, r, 0.001, lim);
  EXPECT_EQ(in.knob_updown_rad, kKnobUpDownMax_rad);
  EXPECT_EQ(in.knob_leftright_rad, -kKnobLeftRightMax_rad);
  r.knob_updown_rad_per_s = -1.0;
  in = integrateHandle(in, r, 0.001, lim);
  EXPECT_NEAR(in.knob_updown_rad, kKnobUpDownMax_rad - 0.001, 1e-12);
  // Rotation accumulates over turns, bounded by what session files hold.
  r = HandleRates();
  r.rotation_rad_per_s = 2.0;
  HandleInput rot;
  for (int k = 0; k < 5000; ++k) rot = integrateHandle(rot, r, 0.001, lim);
  EXPECT_NEAR(rot.rotation_rad, 10.0, 1e-9);
  rot.rotation_rad = lim.rotation_max_rad;
  rot = integrateHandle(rot, r, 0.001, lim);
  EXPECT_EQ(rot.rotation_rad, lim.rotation_max_rad);
  // Non-finite rates move nothing.
  r = HandleRates();
  r.insertion_m_per_s = std::nan("");
  r.rotation_rad_per_s = INFINITY;
  const HandleInput same = integrateHandle(rot, r, 0.001, lim);
  EXPECT_EQ(same.insertion_m, rot.insertion_m);
  EXPECT_EQ(same.rotation_rad, rot.rotation_rad);
}

TEST(IntegrateHandle, CentreKnobsReturnsToNeutralWithoutOvershoot) {
  HandleInput in;
  in.knob_updown_rad = 0.01;
  in.knob_leftright_rad = -0.0105;
  HandleRates r;
  r.centre_knobs = true;
  r.knob_return_rad_per_s = 1.0;
  r.knob_updown_rad_per_s = 5.0;  // ignored while centring
  in = integrateHandle(in, r, 0.004, HandleLimits());
  EXPECT_NEAR(in.knob_updown_rad, 0.006, 1e-15);
  EXPECT_NEAR(in.knob_leftright_rad, -0.0065, 1e-15);
  for (int k = 0; k < 5; ++k) in = integrateHandle(in, r, 0.004, HandleLimits());
  EXPECT_EQ(in.knob_updown_rad, 0.0);
  EXPECT_EQ(in.knob_leftright_rad, 0.0);
}

TEST(RatesFromControls, KeysSticksDeadZoneAndFast) {
  ControlSpeeds s;
  ControlState c;
  EXPECT_EQ(ratesFromControls(c, s).insertion_m_per_s, 0.0);
  c.push = true;
  EXPECT_DOUBLE_EQ(ratesFromControls(c, s).insertion_m_per_s, s.insertion_m_per_s);
  c.pull = true;  // both keys: they cancel
  EXPECT_EQ(ratesFromControls(c, s).insertion_m_per_s, 0.0);
  c = ControlState();
  c.rotate_ccw = true;
  c.tip_up = true;
  c.tip_left = true;
  c.fast = true;
  const HandleRates r = ratesFromControls(c, s);
  EXPECT_DOUBLE_EQ(r.rotation_rad_per_s, -s.fast_factor * s.rotation_rad_per_s);
  EXPECT_DOUBLE_EQ(r.knob_updown_rad_per_s, s.fast_factor * s.knob_rad_per_s);
  EXPECT_DOUBLE_EQ(r.knob_leftright_rad_per_s, -s.fast_factor * s.knob_rad_per_s);
  // Sticks: nothing inside the dead zone, proportional beyond, full at full deflection.
  c = ControlState();
  c.axis_insertion = 0.9 * s.dead_zone;
  EXPECT_EQ(ratesFromControls(c, s).insertion_m_per_s, 0.0);
  c.axis_insertion = s.dead_zone + 0.5 * (1 - s.dead_zone);
  EXPECT_NEAR(ratesFromControls(c, s).insertion_m_per_s, 0.5 * s.insertion_m_per_s, 1e-12);
  c.axis_insertion = -1.0;
  EXPECT_DOUBLE_EQ(ratesFromControls(c, s).insertion_m_per_s, -s.insertion_m_per_s);
  // A key and the stick together saturate at full speed.
  c.axis_rotation = 1.0;
  c.rotate_cw = true;
  EXPECT_DOUBLE_EQ(ratesFromControls(c, s).rotation_rad_per_s, s.rotation_rad_per_s);
  c = ControlState();
  c.axis_updown = std::nan("");
  EXPECT_EQ(ratesFromControls(c, s).knob_updown_rad_per_s, 0.0);
}

TEST(OperatorSource, ScriptedSetUpThenTheOperator) {
  test::TempDir dir;
  std::string text = test::smallScenarioText();
  text.replace(text.find("{\"kind\": \"rest\"}"), 16, "{\"kind\": \"scripted\", \"until_s\": 0.6}");
  const Scenario sc = loadScenario(dir.write("s.json", text));
  SharedRates rates;
  HandleRates r;
  r.insertion_m_per_s = 0.05;
  rates.set(r);
  const InputSource src = operatorSource(sc, sc.dt_s, HandleLimits(), rates);
  // Set-up: the script at k dt (dt = 10 ms, 60 steps before 0.6 s).
  for (long k : {0L, 30L, 51L, 59L}) {
    const HandleInput a = src(k, HandleInput()), b = scriptedInput(sc.script, k * sc.dt_s);
    EXPECT_EQ(a.insertion_m, b.insertion_m) << k;
    EXPECT_EQ(a.rotation_rad, b.rotation_rad) << k;
  }
  // Then the operator's rates from wherever the handle is.
  HandleInput prev;
  prev.insertion_m = 0.3;
  prev.knob_updown_rad = 0.2;
  const HandleInput op = src(60, prev);
  EXPECT_NEAR(op.insertion_m, 0.3 + 0.05 * sc.dt_s, 1e-15);
  EXPECT_EQ(op.knob_updown_rad, 0.2);
  // Autopilot: the script throughout.
  const InputSource auto_src = operatorSource(sc, sc.dt_s, HandleLimits(), rates, /*autopilot=*/true);
  EXPECT_EQ(auto_src(130, prev).insertion_m, scriptedInput(sc.script, 1.3).insertion_m);
}

TEST(HandleLimits, FromTheScopeModel) {
  ScopeParams p;
  const ScopeModel m = buildScopeModel(p, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitY(), Vec3::Zero());
  const HandleLimits l = handleLimitsOf(m);
  EXPECT_GT(l.insertion_max_m, p.working_length_m - 2 * p.segment_length_m);
  EXPECT_LE(l.insertion_max_m, p.working_length_m);
  // Exactly what the scope model accepts.
  HandleInput deep;
  deep.insertion_m = 5.0;
  EXPECT_EQ(clampHandleInput(m, deep).insertion_m, l.insertion_max_m);
}

// A scripted operator: push, rotate, steer, pull back, with the keys' on/off steps.
HandleRates scriptedRates(long step) {
  ControlState c;
  c.push = step < 600 || (step >= 900 && step < 1100);
  c.rotate_cw = step >= 300 && step < 700;
  c.tip_up = step >= 400 && step < 500;
  c.tip_right = step >= 450 && step < 520;
  c.pull = step >= 700 && step < 800;
  c.fast = step >= 200 && step < 400;
  c.centre_knobs = step >= 1000;
  return ratesFromControls(c);
}

TEST(PhysicsLoop, HeadlessWorldSessionReplaysBitIdentically) {
  test::TempDir dir;
  const Scenario sc = findScenario("free_insertion");
  const std::string path = dir.file("train.jsonl");
  PhysicsLoopResult recorded;
  Snapshot snap;
  std::vector<double> insertion_m;
  {
    WorldSimulation sim(sc);
    SessionHeader header = sessionHeaderFor(sc, "test");
    header.mode = "interactive";
    SessionWriter writer(path, header);
    const HandleLimits lim = handleLimitsOf(sim.model().scope);
    // The same code path as colosim train, the rates scripted by step instead of polled.
    InputSource source = [&](long step, const HandleInput& prev) {
      const HandleInput in = integrateHandle(prev, scriptedRates(step), sc.dt_s, lim);
      insertion_m.push_back(in.insertion_m);
      return in;
    };
    PhysicsLoopOptions opt;
    opt.real_time = false;
    opt.max_steps = 1200;
    PhysicsLoop loop(sim, sc.scoring, &writer, source, opt);
    loop.start();
    while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    loop.stop();
    ASSERT_TRUE(loop.latest(snap));
    recorded = loop.finish();
    EXPECT_EQ(recorded.final_state_hash, sim.stateHash());
  }
  EXPECT_EQ(recorded.steps, 1200);
  EXPECT_EQ(snap.steps, 1200);
  EXPECT_TRUE(snap.has_scene);
  EXPECT_EQ(snap.telemetry.input.insertion_m, insertion_m.back());
  // The scope went in (0.6 s at 3 cm/s, 0.2 s of it at 9 cm/s) and the tip moved inside.
  EXPECT_GT(insertion_m[650], 0.02);
  EXPECT_GT(snap.scene.scope_centreline_m.size(), 2u);

  const ReplayPlan plan = planReplay(path);
  EXPECT_EQ(plan.session.header.mode, "interactive");
  EXPECT_TRUE(plan.session.complete);
  EXPECT_EQ(plan.session.steps, 1200);
  EXPECT_GT(plan.session.inputs.size(), 100u);  // the ramps change the input every step
  WorldSimulation again(plan.scenario);
  const ReplayResult r = replay(plan, again);
  EXPECT_TRUE(r.hashOk()) << r.mismatch;
  EXPECT_TRUE(r.final_hash_checked);
  EXPECT_EQ(r.checkpoints_checked, 1);
  EXPECT_EQ(r.final_state_hash, recorded.final_state_hash);
  EXPECT_EQ(r.scores, recorded.scores);
  // The state moved away from the start.
  WorldSimulation start(plan.scenario);
  EXPECT_NE(start.stateHash(), recorded.final_state_hash);
}

// A variable-stiffness scope (issue 20) whose level the operator switches (key F: the
// rates name the level from step 300 on): the session records the level and replays
// bit-identically; without the switch the run ends elsewhere.
TEST(PhysicsLoop, StiffnessLevelIsRecordedAndReplaysBitIdentically) {
  test::TempDir dir;
  // The shipped variable-stiffness design with its section over the whole tube (so that
  // the inserted part changes), and free_insertion naming it.
  nlohmann::json design = nlohmann::json::parse(test::readFile(std::string(COLOSIM_ASSET_DIR) + "/scopes/variable_stiffness.json"));
  design["variable_stiffness"]["from_m"] = 0.0;
  const std::string design_path = dir.write("vs.json", design.dump(2));
  nlohmann::json scen = nlohmann::json::parse(test::readFile(std::string(COLOSIM_ASSET_DIR) + "/scenarios/free_insertion.json"));
  scen["anatomy"] = std::string(COLOSIM_ASSET_DIR) + "/" + scen["anatomy"].get<std::string>();
  scen["params"] = std::string(COLOSIM_ASSET_DIR) + "/" + scen["params"].get<std::string>();
  scen["scope"] = design_path;
  const Scenario sc = loadScenario(dir.write("vs_scenario.json", scen.dump(2)));
  auto record = [&](const std::string& path, bool switch_level) {
    WorldSimulation sim(sc);
    EXPECT_EQ(sim.model().scope.params.variable_stiffness.levels.size(), 4u);
    SessionHeader header = sessionHeaderFor(sc, "test");
    header.mode = "interactive";
    SessionWriter writer(path, header);
    const HandleLimits lim = handleLimitsOf(sim.model().scope);
    int level = -1;
    InputSource source = [&](long step, const HandleInput& prev) {
      HandleRates rates = scriptedRates(step);
      // Three presses of F: levels 1, 2, 3 (from the default 0).
      if (switch_level && (step == 300 || step == 301 || step == 302)) level = nextStiffnessLevel(sim.model().scope, level);
      rates.stiffness_level = level;
      return integrateHandle(prev, rates, sc.dt_s, lim);
    };
    PhysicsLoopOptions opt;
    opt.real_time = false;
    opt.max_steps = 1200;
    PhysicsLoop loop(sim, sc.scoring, &writer, source, opt);
    loop.run();
    EXPECT_EQ(level, switch_level ? 3 : -1);
    return loop.finish();
  };
  const std::string path = dir.file("vs.jsonl");
  const PhysicsLoopResult recorded = record(path, true);
  const PhysicsLoopResult plain = record(dir.file("plain.jsonl"), false);
  EXPECT_NE(recorded.final_state_hash, plain.final_state_hash);
  EXPECT_NE(test::readFile(path).find("\"stiffness_level\":3"), std::string::npos);
  EXPECT_EQ(test::readFile(dir.file("plain.jsonl")).find("stiffness_level"), std::string::npos);

  const ReplayPlan plan = planReplay(path);
  ASSERT_TRUE(plan.session.complete);
  EXPECT_EQ(plan.session.inputs.back().input.stiffness_level, 3);
  WorldSimulation again(plan.scenario);
  const ReplayResult r = replay(plan, again);
  EXPECT_TRUE(r.hashOk()) << r.mismatch;
  EXPECT_TRUE(r.final_hash_checked);
  EXPECT_EQ(r.final_state_hash, recorded.final_state_hash);
}

TEST(PhysicsLoop, RatesChangedFromAnotherThreadAreRecordedAsUsed) {
  // The controls change at random moments on another thread while the loop runs in real
  // time: whatever each step used is what the session holds, so the replay matches.
  test::TempDir dir;
  const Scenario sc = loadScenario(dir.write("small.json", test::smallScenarioText()));
  const std::string path = dir.file("s.jsonl");
  PhysicsLoopResult recorded;
  {
    test::FakeSimulation sim(sc);
    SessionHeader header = sessionHeaderFor(sc, "test");
    header.mode = "interactive";
    SessionWriter writer(path, header);
    SharedRates rates;
    PhysicsLoopOptions opt;
    opt.max_steps = 250;  // 2.5 s at dt = 10 ms, paced in real time
    PhysicsLoop loop(sim, sc.scoring, &writer, operatorSource(sc, sim.dt_s(), HandleLimits(), rates), opt);
    loop.start();
    std::mt19937 rng(42);
    std::uniform_int_distribution<int> coin(0, 1);
    while (loop.running()) {
      ControlState c;
      c.push = coin(rng);
      c.pull = coin(rng);
      c.rotate_cw = coin(rng);
      c.tip_up = coin(rng);
      c.fast = coin(rng);
      rates.set(ratesFromControls(c));
      std::this_thread::sleep_for(std::chrono::milliseconds(3));
    }
    recorded = loop.finish();
  }
  const ReplayPlan plan = planReplay(path);
  EXPECT_GT(plan.session.inputs.size(), 5u);
  test::FakeSimulation again(plan.scenario);
  const ReplayResult r = replay(plan, again);
  EXPECT_TRUE(r.hashOk()) << r.mismatch;
  EXPECT_TRUE(r.final_hash_checked);
  EXPECT_EQ(r.final_state_hash, recorded.final_state_hash);
  // Real-time pacing: 250 steps of 10 ms cannot finish before 2.49 s of wall time.
  EXPECT_GE(recorded.stats.wall_s, 249 * sc.dt_s);
  EXPECT_LE(recorded.stats.steps_per_s, 250.0 / (249 * sc.dt_s));
  EXPECT_EQ(recorded.stats.steps, 250);
}

// A fake simulation slower than real time.
class SlowSimulation : public test::FakeSimulation {
 public:
  using FakeSimulation::FakeSimulation;
  void step(const HandleInput& in) override {
    std::this_thread::sleep_for(std::chrono::milliseconds(4));
    FakeSimulation::step(in);
  }
};

TEST(PhysicsLoop, FallingBehindDropsTimeAndSaysSoOnce) {
  test::TempDir dir;
  std::string text = test::smallScenarioText();
  text.replace(text.find("\"dt_s\": 0.01"), 12, "\"dt_s\": 0.001");
  const Scenario sc = loadScenario(dir.write("small.json", text));
  SlowSimulation sim(sc);
  SharedRates rates;
  PhysicsLoopOptions opt;
  opt.max_steps = 60;
  opt.max_catch_up_steps = 10;
  std::vector<std::string> warnings;
  PhysicsLoop loop(sim, sc.scoring, nullptr, operatorSource(sc, sim.dt_s(), HandleLimits(), rates), opt,
                   [&](const std::string& m) { warnings.push_back(m); });
  loop.run();
  const PhysicsLoopResult r = loop.finish();
  EXPECT_EQ(r.steps, 60);
  EXPECT_GE(r.stats.drop_episodes, 2);  // 4 ms a step: 10 steps behind within ~14 steps, again and again
  EXPECT_GT(r.stats.dropped_steps, 20);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("behind real time"), std::string::npos);
  EXPECT_LT(r.stats.steps_per_s, 500.0);
  EXPECT_GT(r.stats.step_ms_median, 3.0);
}

// A simulation whose step fails (as a solver might) at step 40.
class FailingSimulation : public test::FakeSimulation {
 public:
  using FakeSimulation::FakeSimulation;
  void step(const HandleInput& in) override {
    if (++calls_ == 41) throw std::runtime_error("step failed");
    FakeSimulation::step(in);
  }

 private:
  int calls_ = 0;
};

TEST(PhysicsLoop, AStepErrorOnTheLoopThreadReachesTheCallerWithoutAnEndLine) {
  test::TempDir dir;
  const Scenario sc = loadScenario(dir.write("small.json", test::smallScenarioText()));
  const std::string path = dir.file("s.jsonl");
  FailingSimulation sim(sc);
  SharedRates rates;
  PhysicsLoopOptions opt;
  opt.real_time = false;
  {
    SessionWriter writer(path, sessionHeaderFor(sc, "test"));
    PhysicsLoop loop(sim, sc.scoring, &writer, operatorSource(sc, sim.dt_s(), HandleLimits(), rates, true), opt);
    loop.start();
    while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_THROW(loop.finish(), std::runtime_error);
  }
  // Like a crash: the session replays up to its last checkpoint (none here: 40 steps of
  // 10 ms, the first checkpoint is after 100).
  const Session s = readSession(path);
  EXPECT_FALSE(s.complete);
  EXPECT_TRUE(s.truncated);
}

// Pause (colosim train's P): no step while paused, the pause recorded as two events at
// the same step, and the trajectory that of a run never paused.
TEST(PhysicsLoop, PauseStopsSimulatedTimeAndLeavesTheTrajectoryAlone) {
  test::TempDir dir;
  const Scenario sc = loadScenario(dir.write("small.json", test::smallScenarioText()));
  SharedRates rates;
  PhysicsLoopOptions opt;
  opt.real_time = false;
  opt.max_steps = 300;
  uint64_t unpaused_hash = 0;
  {
    test::FakeSimulation sim(sc);
    PhysicsLoop loop(sim, sc.scoring, nullptr, operatorSource(sc, sim.dt_s(), HandleLimits(), rates, true), opt);
    loop.run();
    unpaused_hash = loop.finish().final_state_hash;
  }
  const std::string path = dir.file("paused.jsonl");
  test::FakeSimulation sim(sc);
  SessionWriter writer(path, sessionHeaderFor(sc, "test"));
  // The pause is asked for from the physics thread itself before step 100 (so the test
  // does not race the loop): the loop sees it at the next boundary, after 101 steps.
  const InputSource script = operatorSource(sc, sim.dt_s(), HandleLimits(), rates, true);
  PhysicsLoop* loop_ptr = nullptr;
  InputSource source = [&](long step, const HandleInput& prev) {
    if (step == 100) loop_ptr->setPaused(true);
    return script(step, prev);
  };
  PhysicsLoop loop(sim, sc.scoring, &writer, source, opt);
  loop_ptr = &loop;
  loop.start();
  while (!loop.paused()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  Snapshot snap;
  loop.latest(snap);
  const long paused_at = snap.steps;
  EXPECT_EQ(paused_at, 101);
  for (int k = 0; k < 20; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    loop.latest(snap);
    EXPECT_EQ(snap.steps, paused_at);  // simulated time stands still
  }
  EXPECT_TRUE(loop.running());
  loop.setPaused(false);
  while (loop.running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const PhysicsLoopResult r = loop.finish("end");
  EXPECT_EQ(r.steps, 300);
  EXPECT_EQ(r.stats.pauses, 1);
  EXPECT_GT(r.stats.paused_s, 0.05);
  EXPECT_EQ(r.final_state_hash, unpaused_hash);
  const Session s = readSession(path);
  ASSERT_EQ(s.events.size(), 3u);  // the fake's solver_limited at 150, paused, resumed
  std::vector<std::string> names;
  for (const SessionEvent& e : s.events)
    if (e.name != "solver_limited") {
      names.push_back(e.name);
      EXPECT_EQ(e.step, paused_at);
    }
  EXPECT_EQ(names, (std::vector<std::string>{"paused", "resumed"}));
  EXPECT_EQ(s.summary["interactive"]["ended_by"], "end");
  EXPECT_EQ(s.summary["interactive"]["pauses"], 1);
}

TEST(PhysicsLoop, SnapshotsOnlyWhenNewer) {
  test::TempDir dir;
  const Scenario sc = loadScenario(dir.write("small.json", test::smallScenarioText()));
  test::FakeSimulation sim(sc);
  SharedRates rates;
  PhysicsLoopOptions opt;
  opt.real_time = false;
  opt.max_steps = 7;
  PhysicsLoop loop(sim, sc.scoring, nullptr, operatorSource(sc, sim.dt_s(), HandleLimits(), rates, true), opt);
  Snapshot s;
  EXPECT_FALSE(loop.latest(s));  // nothing published before the loop runs
  loop.run();
  ASSERT_TRUE(loop.latest(s));
  EXPECT_EQ(s.steps, 7);
  EXPECT_FALSE(s.has_scene);
  EXPECT_NEAR(s.telemetry.time_s, 7 * sc.dt_s, 1e-12);
  EXPECT_FALSE(loop.latest(s));  // nothing newer
  loop.finish();
  EXPECT_THROW(loop.finish(), std::logic_error);
}

TEST(NewSessionPath, DatedNamesThatNeverOverwrite) {
  test::TempDir dir;
  const std::string folder = dir.file("sessions/nested");
  const auto when = std::chrono::system_clock::now();
  const std::string a = newSessionPath(folder, "free insertion/x", when);
  const std::string b = newSessionPath(folder, "free insertion/x", when);
  EXPECT_NE(a, b);
  EXPECT_TRUE(std::filesystem::exists(a));
  EXPECT_TRUE(std::filesystem::exists(b));
  const std::string name = std::filesystem::path(a).filename().string();
  // YYYYMMDD-HHMMSS_<scenario>.jsonl with unsafe characters replaced.
  EXPECT_EQ(name.size(), std::string("20260101-000000_free_insertion_x.jsonl").size()) << name;
  EXPECT_EQ(name.substr(8, 1), "-");
  EXPECT_NE(name.find("_free_insertion_x.jsonl"), std::string::npos) << name;
  EXPECT_NE(std::filesystem::path(b).filename().string().find("_free_insertion_x-2.jsonl"), std::string::npos);
  // An existing file with the next name is skipped, not replaced.
  std::string third = b;
  third.replace(third.find("-2.jsonl"), 8, "-3.jsonl");
  test::TempDir unused;
  { std::ofstream(third) << "keep"; }
  const std::string c = newSessionPath(folder, "free insertion/x", when);
  EXPECT_NE(c, third);
  EXPECT_EQ(test::readFile(third), "keep");
}

}  // namespace
}  // namespace colosim
