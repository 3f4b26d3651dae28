// Replay against the Simulation interface: bit-identical replays with the colon-only
// simulation, many sessions scored at once equal to one at a time and in order.
#include "trainer/replay.h"

#include <atomic>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/colon_step.h"
#include "core/tension_law.h"
#include "fake_simulation.h"
#include "fixture.h"
#include "session_fixture.h"
#include "trainer/assets.h"
#include "trainer/colon_simulation.h"
#include "trainer/scenario.h"
#include "trainer/strict_json.h"
#include "trainer/telemetry.h"

namespace colosim {
namespace {

std::string withSeed(int seed) {
  std::string t = test::smallScenarioText();
  const auto p = t.find("\"seed\": 7");
  return t.replace(p, 9, "\"seed\": " + std::to_string(seed));
}

TEST(Replay, ColonOnlySimulationReplaysBitIdentically) {
  test::TempDir dir;
  const Scenario sc = loadScenario(dir.write("small.json", test::smallScenarioText()));
  const std::string path = dir.file("colon.jsonl");
  RunResult recorded;
  {
    ColonOnlySimulation sim(sc);
    SessionWriter w(path, sessionHeaderFor(sc, "test"));
    recorded = runScenario(sc, sim, &w);
  }
  const ReplayPlan plan = planReplay(path);
  for (int run = 0; run < 2; ++run) {
    ColonOnlySimulation sim(plan.scenario);
    const ReplayResult r = replay(plan, sim);
    EXPECT_EQ(r.final_state_hash, recorded.final_state_hash) << "run " << run;
    EXPECT_TRUE(r.hashOk()) << r.mismatch;
    EXPECT_EQ(r.checkpoints_checked, 2);
  }
  // The colon moved (it settles under gravity): the hash is not that of the rest state.
  ColonOnlySimulation rest(plan.scenario);
  EXPECT_NE(rest.stateHash(), recorded.final_state_hash);
}

TEST(Replay, ColonOnlyStartStatesAndOverrides) {
  test::TempDir dir;
  const Scenario rest = loadScenario(dir.write("rest.json", test::smallScenarioText()));
  std::string text = test::smallScenarioText();
  text.replace(text.find("{\"kind\": \"rest\"}"), 16, "{\"kind\": \"settled\", \"settle_s\": 0.5}");
  const Scenario settled = loadScenario(dir.write("settled.json", text));
  text = test::smallScenarioText();
  text.replace(text.find("\"script\": ["), 11, "\"overrides\": {\"patient_position\": \"supine\"}, \"script\": [");
  const Scenario supine = loadScenario(dir.write("supine.json", text));
  EXPECT_EQ(supine.overrides.patient_position.value(), "supine");
  ColonOnlySimulation a(rest), b(settled), c(supine);
  EXPECT_EQ(b.time_s(), 0.0);  // the session's clock starts after settling
  EXPECT_NE(a.stateHash(), b.stateHash());  // but the colon has moved
  EXPECT_EQ(a.stateHash(), c.stateHash());  // same rest state ...
  EXPECT_NE(a.model().gravity_m_per_s2, c.model().gravity_m_per_s2);  // ... different gravity
}

TEST(Replay, TheColonAloneAtRestIsNotScoredAsDiscomfort) {
  // free_insertion starts settled; with no scope nothing stretches the colon or the
  // mesentery beyond carrying the colon's weight, so neither threshold may be reached.
  const Scenario sc = findScenario("free_insertion");
  ColonOnlySimulation sim(sc);
  const RunResult r = runScenario(sc, sim, nullptr, {}, 3000);
  // Measured from the resting colon (restingColon): 0.048 of the colon's weight, what the
  // start's settling (2 s at 1 ms) leaves undone. From the lifters' rest positions the same
  // colon read 1-3 (a firm attachment beside the free sigmoid: 6).
  std::printf("the colon alone at rest: mesentery stretch %.4g\n", r.scores["peak_mesentery_stretch"].get<double>());
  EXPECT_LT(r.scores["peak_mesentery_stretch"].get<double>(), 0.25);
  EXPECT_EQ(r.scores["mesentery_stretch_time_pct"].get<double>(), 0.0);
  // The hanging colon is stretched a little by its own weight (measured 0.7 %, at the
  // hepatic flexure), well short of the discomfort threshold (3 %).
  EXPECT_GT(r.scores["peak_colon_stretch"].get<double>(), 0.0);
  EXPECT_LT(r.scores["peak_colon_stretch"].get<double>(), 0.5 * sc.scoring.discomfort_strain);
  EXPECT_EQ(r.scores["discomfort_time_pct"].get<double>(), 0.0);
}

TEST(Replay, ManySessionsScoreAsOneAtATimeAndInOrder) {
  test::TempDir dir;
  std::vector<std::string> paths;
  for (int i = 0; i < 6; ++i) {
    const Scenario sc = loadScenario(dir.write("sc" + std::to_string(i) + ".json", withSeed(i)));
    const std::string p = dir.file("s" + std::to_string(i) + ".jsonl");
    test::FakeSimulation sim(sc);
    SessionWriter w(p, sessionHeaderFor(sc, "test"));
    // Different lengths, so that threads finish out of order.
    runScenario(sc, sim, &w, {}, 250 - 30 * i);
    paths.push_back(p);
  }
  std::vector<nlohmann::json> alone;
  for (const std::string& p : paths) {
    const std::vector<ReplayResult> one = replaySessions({p}, test::makeFake, 1);
    ASSERT_EQ(one.size(), 1u);
    alone.push_back({{"file", one[0].file}, {"hash", one[0].final_state_hash}, {"scores", one[0].scores}});
  }
  for (unsigned threads : {1u, 3u, 0u}) {
    long last_total = 0;
    std::atomic<long> calls{0};
    const std::vector<ReplayResult> all = replaySessions(paths, test::makeFake, threads, [&](long, long total) {
      last_total = total;
      ++calls;
    });
    ASSERT_EQ(all.size(), paths.size());
    for (size_t i = 0; i < all.size(); ++i) {
      EXPECT_EQ(all[i].file, paths[i]);
      EXPECT_TRUE(all[i].hashOk()) << all[i].mismatch;
      const nlohmann::json j = {{"file", all[i].file}, {"hash", all[i].final_state_hash}, {"scores", all[i].scores}};
      EXPECT_EQ(j, alone[i]) << "threads " << threads << ", session " << i;
    }
    EXPECT_GT(calls.load(), 0);
    EXPECT_EQ(last_total, 6 * 250 - 30 * 15);
  }
  // Different seeds give different states: the comparison above is not vacuous.
  EXPECT_NE(alone[0]["hash"], alone[1]["hash"]);
}

TEST(Replay, ABadSessionStopsTheBatchBeforeAnyWork) {
  test::TempDir dir;
  const Scenario sc = loadScenario(dir.write("sc.json", test::smallScenarioText()));
  const std::string good = dir.file("good.jsonl");
  {
    test::FakeSimulation sim(sc);
    SessionWriter w(good, sessionHeaderFor(sc, "test"));
    runScenario(sc, sim, &w);
  }
  std::string text = test::readFile(good);
  text.replace(text.find("\"version\":1"), 11, "\"version\":9");
  const std::string bad = dir.write("bad.jsonl", text);
  std::atomic<int> built{0};
  SimulationFactory counting = [&](const Scenario& s) {
    ++built;
    return test::makeFake(s);
  };
  test::expectInputError([&] { replaySessions({good, bad}, counting, 2); }, {bad + ":1:", "version"});
  EXPECT_EQ(built.load(), 0);
}

TEST(Telemetry, NetTurnsOfCirclesAndBends) {
  const double pi = 3.14159265358979323846;
  std::vector<Vec3> circle, s_shape;
  for (int i = 0; i <= 64; ++i) {
    const double a = 2 * pi * i / 64;
    circle.push_back(Vec3(std::cos(a), std::sin(a), 0.3 * a));  // a helix: projection is a circle
  }
  for (int i = 0; i <= 64; ++i) {
    const double a = pi * i / 32;  // two half circles turning opposite ways
    s_shape.push_back(i <= 32 ? Vec3(std::cos(a), std::sin(a), 0) : Vec3(-2 + std::cos(a - pi) , -std::sin(a - pi), 0));
  }
  const Vec3 z(0, 0, 1);
  // The 64-gon's tangents turn by 63/64 of a circle between its first and last segments.
  EXPECT_NEAR(netTurns(circle, z), 63.0 / 64.0, 1e-9);
  std::vector<Vec3> reversed(circle.rbegin(), circle.rend());
  EXPECT_NEAR(netTurns(reversed, z), -63.0 / 64.0, 1e-9);
  EXPECT_NEAR(netTurns(circle, -z), -63.0 / 64.0, 1e-9);
  EXPECT_NEAR(netTurns(s_shape, z), 0.0, 0.05);
}

TEST(Telemetry, MesenteryStretchIsLifterLoadOverWeight) {
  // A straight colon displaced uniformly by d: every lifter carries k d per unit length.
  const int n = 11;
  Points q(3, n);
  for (int i = 0; i < n; ++i) q.col(i) = Vec3(0.02 * i, 0, 0);
  const double rho = 0.4, k = 100.0, g = 9.81, d = 0.05;
  const ColonModel m = buildColonModelFromPoints(q, Eigen::VectorXd::Constant(n, 0.02), rho, k, 1.0,
                                                 Vec3(0, 0, -g), std::make_shared<VoigtLaw>(28.9, 0.05));
  ColonState s = makeColonState(m);
  EXPECT_EQ(mesenteryStretch(m, s), 0.0);
  s.q.row(2).array() += d;
  EXPECT_NEAR(mesenteryStretch(m, s), k * d / (rho * g), 1e-9);
  // One point pulled further: against the lifter forces computed with the dense matrix.
  s.q.col(4).y() += 0.1;
  double brute = 0;
  for (int i = 0; i < n; ++i) {
    Vec3 f = Vec3::Zero();
    for (int j = 0; j < n; ++j) f += m.mesentery_K.at(i, j) * (s.q.col(j) - m.q_rest.col(j));
    brute = std::max(brute, f.norm() / (m.mass_rowsum_kg(i) * g));
  }
  EXPECT_NEAR(mesenteryStretch(m, s), brute, 1e-9);
  EXPECT_GT(brute, k * d / (rho * g));
}

// The resting colon (restingColon) is the patient's static equilibrium under gravity: its
// lifters, tension and bending balance the weight, so a colon started there at rest stays
// (one 1 ms step moves no point by more than a micrometre), and the mesentery stretch
// measured against it reads only what is beyond the resting load: 0 there, k d / (rho g)
// for a free colon moved by d from it.
TEST(Telemetry, TheRestingColonIsAStaticEquilibriumAndStretchIsMeasuredFromIt) {
  const Scenario sc = findScenario("free_insertion");
  const WorldModel world = loadWorldModel(sc.anatomy_path, scenarioParameters(sc));
  const ColonModel& m = world.colon;
  const Points resting = restingColon(m);
  const double sag_m = (resting - m.q_rest).colwise().norm().maxCoeff();
  EXPECT_GT(sag_m, 0.005) << "the colon does hang under its weight";
  ColonState s = makeColonState(m);
  s.q = resting;
  EXPECT_EQ(mesenteryStretch(m, s, &resting), 0.0);
  EXPECT_GT(mesenteryStretch(m, s), 0.5) << "from the lifters' rest positions it reads the weight they carry";
  stepColon(m, s, 1e-3);
  const double moved_m = (s.q - resting).colwise().norm().maxCoeff();
  std::printf("resting colon: sag up to %.4f m from the lifters' rest; one 1 ms step from it moves a point %.3g m\n",
              sag_m, moved_m);
  EXPECT_LT(moved_m, 1e-6) << "a static equilibrium";
  // Moved by d as a whole from rest, each lifter carries K d more than at rest: what the
  // same move reads from the lifters' rest positions (the lifters are linear).
  const double d = 0.002;
  s.q = resting;
  s.q.row(2).array() += d;
  ColonState from_q0 = makeColonState(m);
  from_q0.q = m.q_rest;
  from_q0.q.row(2).array() += d;
  EXPECT_GT(mesenteryStretch(m, s, &resting), 0.1);
  EXPECT_NEAR(mesenteryStretch(m, s, &resting), mesenteryStretch(m, from_q0), 1e-9);
}

}  // namespace
}  // namespace colosim
