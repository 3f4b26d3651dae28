// The shipped scenarios run whole on the colon + scope world (trainer/world_simulation.h):
// the alpha loop of sigmoid_untwist is there early and gone at the end, the expert
// session scores better than the novice's (sigmoid_push), and the scripted
// free_insertion gives handle forces of the clinical order (Appleyard et al. 2000).
// Each scenario runs once per process (a shared fixture). ctest runs this binary as two
// processes (tests/CMakeLists.txt): ScenarioRuns.Sigmoid* and ScenarioRuns.Expert* run the
// sigmoid scenarios, every other test the rest, so a test names the process of its
// scenarios and each scenario runs once in the suite. Not in the sanitized build (whole
// scenarios under ASan take too long).
#include <cmath>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "fixture.h"
#include "trainer/expert_sessions.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/world_simulation.h"

namespace colosim {
namespace {

struct ScenarioRun {
  nlohmann::json scores;
  std::vector<double> time_s, loop_turns;  // every step
  double peak_push_N = 0, peak_pull_N = 0, peak_torque_Nm = 0, min_tip_to_caecum_m = 1e9;
  double max_tip_arclength_m = 0;  // furthest the tip got along the colon (rest arclength)
  uint64_t final_state_hash = 0;
};

// Runs a shipped scenario once per process and keeps what the tests look at. "NAME@FILE"
// runs it with the parameter file assets/params/FILE.json instead of its own.
const ScenarioRun& runOnce(const std::string& name) {
  static std::map<std::string, ScenarioRun> runs;
  auto it = runs.find(name);
  if (it != runs.end()) return it->second;
  const size_t at = name.find('@');
  Scenario sc = findScenario(name.substr(0, at));
  if (at != std::string::npos) {
    const std::string file = sc.params_path.substr(0, sc.params_path.rfind('/') + 1) + name.substr(at + 1) + ".json";
    useParameterFile(sc, file);
  }
  WorldSimulation sim(sc);
  ScenarioRun r;
  RunHooks hooks;
  hooks.on_step = [&r](const Telemetry& t) {
    r.time_s.push_back(t.time_s);
    r.loop_turns.push_back(t.loop_turns);
    r.peak_push_N = std::max(r.peak_push_N, t.handle_force_N);
    r.peak_pull_N = std::max(r.peak_pull_N, -t.handle_force_N);
    r.peak_torque_Nm = std::max(r.peak_torque_Nm, std::abs(t.handle_torque_Nm));
    r.min_tip_to_caecum_m = std::min(r.min_tip_to_caecum_m, t.tip_to_caecum_m);
    r.max_tip_arclength_m = std::max(r.max_tip_arclength_m, t.tip_arclength_m);
  };
  r.scores = runScenario(sc, sim, nullptr, hooks).scores;
  r.final_state_hash = sim.stateHash();
  return runs.emplace(name, std::move(r)).first->second;
}

// Smallest |loop_turns| over [t0, t1] s.
double minLoop(const ScenarioRun& r, double t0, double t1) {
  double m = 1e9;
  for (size_t i = 0; i < r.time_s.size(); ++i)
    if (r.time_s[i] >= t0 && r.time_s[i] <= t1) m = std::min(m, std::abs(r.loop_turns[i]));
  return m;
}
// Largest |loop_turns| over [t0, t1] s.
double maxLoop(const ScenarioRun& r, double t0, double t1) {
  double m = 0;
  for (size_t i = 0; i < r.time_s.size(); ++i)
    if (r.time_s[i] >= t0 && r.time_s[i] <= t1) m = std::max(m, std::abs(r.loop_turns[i]));
  return m;
}

TEST(ScenarioRuns, SigmoidUntwistLoopIsThereEarlyAndGoneAtTheEnd) {
  const ScenarioRun& r = runOnce("sigmoid_untwist");
  // The start state's alpha loop stands through the set-up (0-2 s), measured on the
  // simulated scope shape. (On the one patient of session 9, the rectum held in the pelvis
  // and the colon's bending, the withdrawal takes it out in its first 0.7 s: the first
  // second of the manoeuvre is no longer asked for.)
  EXPECT_GE(minLoop(r, 0.0, 2.0), 1.0);
  // After the turning withdrawal and through the advance (the last 10 s): no crossing.
  EXPECT_EQ(maxLoop(r, 18.0, 28.0), 0.0);
  EXPECT_EQ(r.loop_turns.back(), 0.0);
}

TEST(ScenarioRuns, ExpertScoresBetterThanTheNovice) {
  const ScenarioRun& expert = runOnce("sigmoid_untwist");
  const ScenarioRun& novice = runOnce("sigmoid_push");
  // The novice's loop is still there at the end.
  EXPECT_GE(std::abs(novice.loop_turns.back()), 1.0);
  // Discomfort is the colon stretched beyond 3 % of its rest length: pushing on the loop
  // stretches the sigmoid against its attachments (measured: 29 % at the most, discomfort
  // 100 % of the scored time, index 3.9 s), the expert's withdrawal lets it go within
  // seconds (5.7 %, 4.4 %, 0.013 s). (Before session 21 it was the mesentery's load, above
  // its threshold from the first step in both runs, and ranked them the wrong way.)
  for (const char* key : {"loop_time_s", "peak_handle_force_N", "discomfort_index", "discomfort_time_pct"}) {
    const double e = expert.scores.at(key).get<double>(), n = novice.scores.at(key).get<double>();
    EXPECT_LT(e, n) << key << ": expert " << e << ", novice " << n;
  }
  // And by a margin on the loop: most of the novice's scored 26 s (measured 19.2 s on the
  // one patient, 24 s before), a few of the expert's (0.7 s).
  EXPECT_LT(expert.scores.at("loop_time_s").get<double>(), 6.0);
  EXPECT_GT(novice.scores.at("loop_time_s").get<double>(), 15.0);
  // Issue 21: the expert's discomfort is not saturated, and steering keeps the lumen in
  // view (measured 66 % of the scored 26 s, red-out 2.4 s).
  const double scored_s = expert.scores.at("duration_s").get<double>();
  EXPECT_LT(expert.scores.at("discomfort_time_pct").get<double>(), 60.0);
  EXPECT_GT(expert.scores.at("lumen_visible_pct").get<double>(), 50.0);
  EXPECT_LT(expert.scores.at("redout_time_s").get<double>(), 0.25 * scored_s);
}

TEST(ScenarioRuns, FreeInsertionHandleForcesOfTheClinicalOrder) {
  const ScenarioRun& r = runOnce("free_insertion");
  std::printf("free_insertion: peak push %.2f N, peak pull %.2f N, peak torque %.3f N m, tip furthest %.3f m along "
              "the colon, closest to the caecal pole %.3f m, time to caecum %s s\n",
              r.peak_push_N, r.peak_pull_N, r.peak_torque_Nm, r.max_tip_arclength_m, r.min_tip_to_caecum_m,
              r.scores.at("time_to_caecum_s").dump().c_str());
  // Appleyard et al. 2000: peak push ~43 N, peak pull ~18 N, peak torque ~1 N m. The
  // scripted insertion on the one patient stays below them (measured 5.8 N, 4.3 N,
  // 0.099 N m): bounds of the order, and no one-step kicks (the 30-60 N pulls of the anus
  // sliding up the scope before the rectum was held in the pelvis, docs/parameters.md).
  EXPECT_GE(r.peak_push_N, 2.0);
  EXPECT_LE(r.peak_push_N, 60.0);
  EXPECT_LT(r.peak_pull_N, 30.0);
  EXPECT_LT(r.peak_torque_Nm, 2.0);
  // The tip passes both flexures into the ascending colon (measured: 1.457 m of the
  // 1.60 m colon). It does not reach the caecum: the colon is not shortened onto the scope
  // enough for the 1.6 m scope (README, known limits). The caecum it reached before stood
  // on the colon folding across the scope (0.17 m track jumps), so it was withdrawn.
  EXPECT_GE(r.max_tip_arclength_m, 1.40);
}

// Issue 16: every shipped scenario keeps the scope in the colon's lumen, measured at every
// step (core/lumen_check.h): no slice centre outside the lumen of its track, adjacent slices
// tracked at most 3 cm of colon apart beyond their own spacing, no interaction point 5 mm
// beyond its wall.
void expectInTheLumen(const std::string& name, const nlohmann::json& scores) {
  EXPECT_EQ(scores.at("lumen_exit_steps").get<long>(), 0) << name;
  EXPECT_LT(scores.at("max_track_jump_m").get<double>(), 0.03) << name;
  EXPECT_LT(scores.at("max_wall_penetration_m").get<double>(), 0.005) << name;
}

TEST(ScenarioRuns, SigmoidScenariosKeepTheScopeInTheLumen) {
  for (const char* name : {"sigmoid_untwist", "sigmoid_push"}) expectInTheLumen(name, runOnce(name).scores);
}

TEST(ScenarioRuns, FreeInsertionKeepsTheScopeInTheLumen) {
  expectInTheLumen("free_insertion", runOnce("free_insertion").scores);
}

// What the patient's colon bending (assets/params/default.json, bending_rigidity) is for:
// on the paper's colon (params/paper.json, no bending resistance) the untwisting
// withdrawal folds the upper rectum and sigmoid across the scope, adjacent slices are
// tracked several cm of colon apart and slices leave their lumen (measured: 176 steps, a
// 0.106 m jump); the tuned patient keeps it in (the test above).
TEST(ScenarioRuns, SigmoidOnThePapersColonFoldsAcrossTheScope) {
  const nlohmann::json& paper = runOnce("sigmoid_untwist@paper").scores;
  EXPECT_GT(paper.at("lumen_exit_steps").get<long>(), 0);
  EXPECT_GT(paper.at("max_track_jump_m").get<double>(), 0.03);
}

// The behaviour pinned for redesigns (tests/golden/behaviour.json, as golden_tests does for
// the other scenarios): the final state of each run here is bit-identical to the pinned one.
void expectThePinnedFinalStates(const std::vector<std::string>& names) {
  const nlohmann::json golden = nlohmann::json::parse(
      test::readFile(std::string(COLOSIM_GOLDEN_DIR) + "/behaviour.json"))["scenario_final_state_hash"];
  for (const std::string& name : names) {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(runOnce(name).final_state_hash));
    EXPECT_EQ(std::string(hex), golden.at(name).get<std::string>()) << name;
  }
}

TEST(ScenarioRuns, SigmoidFinalStatesAreThePinnedOnes) {
  expectThePinnedFinalStates({"sigmoid_untwist", "sigmoid_push"});
}

TEST(ScenarioRuns, FreeInsertionFinalStateIsThePinnedOne) { expectThePinnedFinalStates({"free_insertion"}); }

// The trainer's score card and the session reports compare sessions with the shipped
// expert sessions (assets/sessions/expert/): the scores their end lines recorded must be
// what the runs give today. Split between the two processes: the sessions of the sigmoid
// scenarios in one, every other one in the other.
bool isSigmoidScenario(const std::string& id) { return id == "sigmoid_untwist" || id == "sigmoid_push"; }

void expectTheExpertSessionsScores(bool sigmoid) {
  const std::vector<ExpertSession> experts = loadExpertSessions();
  ASSERT_FALSE(experts.empty());
  for (const ExpertSession& e : experts) {
    if (isSigmoidScenario(e.scenario_id) != sigmoid) continue;
    EXPECT_EQ(e.scores, runOnce(e.scenario_id).scores)
        << e.file << " is stale; record it again (docs/file-formats.md, Expert references)";
  }
}

TEST(ScenarioRuns, SigmoidScenariosScoreAsTheirExpertSessions) { expectTheExpertSessionsScores(true); }

TEST(ScenarioRuns, OtherScenariosScoreAsTheirExpertSessions) { expectTheExpertSessionsScores(false); }

}  // namespace
}  // namespace colosim
