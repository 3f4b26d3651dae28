// Design studies (trainer/study.h, colosim study): strict reading, the seed-0 case against
// colosim run, thread-count invariance, shards merged byte-identical, merge errors and the
// statistics against hand-computed values. Simulations are a few seconds of sigmoid_push.
#include "trainer/study.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "fixture.h"
#include "trainer/strict_json.h"

namespace colosim {
namespace {

// A study of 2 designs x sigmoid_push x 2 strategies x 2 seeds, `duration_s` each.
std::string tinyStudyText(double duration_s = 2.6, const std::string& name = "tiny") {
  return R"({
  "format": "colosim-study", "version": 1, "name": ")" + name + R"(",
  "description": "test study",
  "designs": [{"name": "standard", "scope": "scopes/standard.json"},
              {"name": "stiff", "scope": "scopes/standard.json", "shaft_bending_stiffness_Nm2": 0.06}],
  "scenarios": ["sigmoid_push"],
  "strategies": ["scripted", {"kind": "lumen_following", "end_s": 30}],
  "seeds": [0, 1],
  "duration_s": )" + std::to_string(duration_s) + R"(,
  "report": {"shape_times_s": [2.5]}
})";
}

std::string errorOf(const std::string& text) {
  try {
    parseStudy(text, "s.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void replace(std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

TEST(StudyFile, ReadsTheTinyStudyInCanonicalOrder) {
  const Study s = parseStudy(tinyStudyText(), "s.json");
  EXPECT_EQ(s.name, "tiny");
  ASSERT_EQ(s.designs.size(), 2u);
  EXPECT_FALSE(s.designs[0].shaft_bending_stiffness_Nm2);
  EXPECT_EQ(s.designs[0].scope, "scopes/standard.json");
  EXPECT_EQ(*s.designs[1].shaft_bending_stiffness_Nm2, 0.06);
  ASSERT_EQ(s.strategies.size(), 2u);
  EXPECT_EQ(s.strategies[1].kind, "lumen_following");
  EXPECT_EQ(s.strategies[1].end_s, 30.0);
  const std::vector<StudyCase> cases = studyCases(s);
  ASSERT_EQ(cases.size(), 8u);
  // design outermost, then scenario, strategy, seed
  EXPECT_EQ(cases[1].seed, 1);
  EXPECT_EQ(cases[2].strategy, 1);
  EXPECT_EQ(cases[4].design, 1);
  for (size_t i = 0; i < cases.size(); ++i) EXPECT_EQ(cases[i].index, static_cast<int>(i));
}

TEST(StudyFile, BadKeysAndValuesNameFileKeyAndLine) {
  struct Bad {
    std::string from, to, expect;
  };
  const std::vector<Bad> bad = {
      {"\"description\"", "\"colour\": 1, \"description\"", "s.json:3: colour"},
      {"\"seeds\": [0, 1]", "\"seeds\": [0, -1]", "seeds[1]"},
      {"\"seeds\": [0, 1]", "\"seeds\": [0, 0]", "listed twice"},
      {"\"sigmoid_push\"", "\"no_such_scenario\"", "scenarios[0]"},
      {"{\"name\": \"stiff\"", "{\"name\": \"standard\"", "names two designs"},
      {"0.06", "-1", "designs[1].shaft_bending_stiffness_Nm2"},
      {"\"scripted\"", "\"pushing\"", "strategies[0]"},
      {", \"end_s\": 30", "", "strategies[1].end_s"},
      {"colosim-study", "colosim-scenario", "format"},
      {"\"duration_s\": ", "\"duration_s\": -", "duration_s"},
      {"scopes/standard.json", "scopes/none.json", "designs[0].scope"},
      {"\"shaft_bending_stiffness_Nm2\": 0.06", "\"stiffen_from_s\": 12", "designs[1].stiffen_from_s"},
      {"\"shaft_bending_stiffness_Nm2\": 0.06", "\"stiffness_level\": -1", "designs[1].stiffness_level"},
  };
  for (const Bad& b : bad) {
    std::string text = tinyStudyText();
    replace(text, b.from, b.to);
    const std::string e = errorOf(text);
    EXPECT_NE(e.find("s.json"), std::string::npos) << b.to << ": " << e;
    EXPECT_NE(e.find(b.expect), std::string::npos) << b.to << ": " << e;
  }
  // The line of a bad value is named.
  std::string text = tinyStudyText();
  replace(text, "\"seeds\": [0, 1]", "\"seeds\": [0, 1.5]");
  EXPECT_NE(errorOf(text).find("s.json:8:"), std::string::npos) << errorOf(text);
}

TEST(StudyFile, ShippedStudiesRead) {
  int read = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::asset("studies"))) {
    if (e.path().extension() != ".json") continue;
    const Study s = loadStudy(e.path().string());
    EXPECT_EQ(s.name, e.path().stem().string());
    EXPECT_FALSE(studyCases(s).empty());
    ++read;
  }
  EXPECT_GE(read, 1);
}

TEST(StudySeeds, SeedZeroIsTheScenarioAsShippedAndOthersVaryWithinTheirRanges) {
  const SeedVariant zero = seedVariant(0);
  EXPECT_EQ(zero.operator_speed, 1.0);
  EXPECT_EQ(zero.lifter_stiffness, 1.0);
  EXPECT_EQ(zero.wall_friction, 1.0);
  bool any_differ = false;
  for (int seed = 1; seed <= 50; ++seed) {
    const SeedVariant v = seedVariant(seed);
    EXPECT_GE(v.operator_speed, 0.9);
    EXPECT_LE(v.operator_speed, 1.1);
    EXPECT_GE(v.lifter_stiffness, 0.85);
    EXPECT_LE(v.lifter_stiffness, 1.15);
    EXPECT_GE(v.wall_friction, 0.85);
    EXPECT_LE(v.wall_friction, 1.15);
    any_differ = any_differ || v.operator_speed != seedVariant(1).operator_speed;
  }
  EXPECT_TRUE(any_differ);
  // The same seed gives the same variant (every machine: SplitMix64, no std distribution).
  EXPECT_EQ(seedVariant(7).operator_speed, seedVariant(7).operator_speed);
  // Seed 0 leaves the script as it is; another seed warps it after the scored start.
  const Study s = parseStudy(tinyStudyText(), "s.json");
  const Scenario shipped = findScenario("sigmoid_push");
  StudyCase c;
  const Scenario s0 = caseScenario(s, c);
  ASSERT_EQ(s0.script.size(), shipped.script.size());
  for (size_t k = 0; k < s0.script.size(); ++k) EXPECT_EQ(s0.script[k].t_s, shipped.script[k].t_s);
  c.seed = 1;
  const Scenario s1 = caseScenario(s, c);
  EXPECT_EQ(s1.script[1].t_s, shipped.script[1].t_s);  // the set-up (to 2 s) is not warped
  EXPECT_NEAR(s1.script[2].t_s, 2.0 + 26.0 / seedVariant(1).operator_speed, 1e-12);
}

TEST(StudyStatistics, MeanSdAndStudentIntervalMatchHandComputedValues) {
  const MeanSd m = meanSd({1, 2, 3, 4});
  EXPECT_EQ(m.n, 4);
  EXPECT_DOUBLE_EQ(*m.mean, 2.5);
  EXPECT_NEAR(*m.sd, 1.2909944487358056, 1e-14);  // sqrt(5/3)
  const PairedDifference p = pairedDifference({1, 2, 3, 4});
  ASSERT_TRUE(p.ci95);
  EXPECT_NEAR(p.ci95->first, 0.4457397434226116, 1e-8);  // 2.5 -+ t(0.975, 3) sd / 2, t = 3.182446305
  EXPECT_NEAR(p.ci95->second, 4.554260256577388, 1e-8);
  // t quantiles: table values and the expansion past 30 dof.
  EXPECT_NEAR(studentT975(1), 12.7062047, 1e-6);
  EXPECT_NEAR(studentT975(10), 2.2281389, 1e-6);
  EXPECT_NEAR(studentT975(40), 2.0210754, 1e-6);
  EXPECT_NEAR(studentT975(100), 1.9839715, 1e-6);
  EXPECT_NEAR(studentT975(1000), 1.9623391, 1e-6);
  // n = 1: a mean, no sd, no interval; n = 0: nothing.
  const PairedDifference one = pairedDifference({3});
  EXPECT_EQ(*one.mean_difference, 3.0);
  EXPECT_FALSE(one.ci95);
  EXPECT_FALSE(meanSd({}).mean);
  EXPECT_FALSE(meanSd({5}).sd);
}

TEST(StudySummary, NullMetricsArePairedOnlyWhereBothDesignsHaveThem) {
  StudyResults r;
  r.study = "s";
  r.designs = {"a", "b"};
  r.scenarios = 1, r.strategies = 1, r.seeds = 3;
  const size_t metrics = studyMetricNames().size();
  // time_to_caecum_s: a reaches in 10, 20, never; b in 8, never, 30.
  const std::vector<std::optional<double>> ttc = {10.0, 20.0, std::nullopt, 8.0, std::nullopt, 30.0};
  for (int i = 0; i < 6; ++i) {
    CaseResult c;
    c.index = i;
    c.metrics.assign(metrics, 1.0 + i);
    c.metrics[0] = ttc[static_cast<size_t>(i)];
    r.cases.push_back(c);
  }
  const nlohmann::ordered_json j = studySummaryJson(r);
  EXPECT_EQ(j.begin().key(), "study");
  const auto& b = j["designs"][1];
  EXPECT_EQ(b["cases"], 3);
  EXPECT_DOUBLE_EQ(b["metrics"]["time_to_caecum_s"]["mean"].get<double>(), 19.0);
  EXPECT_DOUBLE_EQ(b["vs_first"]["time_to_caecum_s"]["mean_difference"].get<double>(), -2.0);  // one pair: 8 - 10
  EXPECT_TRUE(b["vs_first"]["time_to_caecum_s"]["ci95"].is_null());
  EXPECT_DOUBLE_EQ(b["vs_first"]["loop_time_s"]["mean_difference"].get<double>(), 3.0);
  EXPECT_EQ(b["vs_first"]["loop_time_s"]["ci95"][0].get<double>(), 3.0);  // all differences equal
  for (const std::string& m : studyMetricNames()) {
    EXPECT_TRUE(b["metrics"].contains(m)) << m;
    EXPECT_TRUE(b["vs_first"].contains(m)) << m;
  }
}

// Shards written from made-up results: merge errors need no simulation.
struct FakeShards {
  test::TempDir dir;
  Study study;
  std::vector<StudyCase> cases;
  explicit FakeShards(const std::string& name = "tiny") {
    study = parseStudy(tinyStudyText(2.6, name), dir.write("s.json", tinyStudyText(2.6, name)));
    cases = studyCases(study);
  }
  std::string write(int k, int n, const std::string& sub) {
    const std::vector<StudyCase> mine = shardCases(cases, k, n);
    std::vector<CaseResult> results;
    for (const StudyCase& c : mine) {
      CaseResult r;
      r.index = c.index;
      r.metrics.assign(studyMetricNames().size(), 0.1 * c.index);
      r.metrics[0] = std::nullopt;
      results.push_back(r);
    }
    return writeShard(study, k, n, mine, results, dir.file(sub));
  }
};

std::string mergeError(const std::vector<std::string>& dirs) {
  try {
    mergeShards(dirs);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(StudyMerge, MissingDuplicateAndForeignShardsAreErrors) {
  FakeShards f;
  f.write(1, 3, "a");
  f.write(2, 3, "b");
  EXPECT_NE(mergeError({f.dir.file("a"), f.dir.file("b")}).find("shard-3-of-3.json"), std::string::npos);
  f.write(3, 3, "c");
  EXPECT_EQ(mergeError({f.dir.file("a"), f.dir.file("b"), f.dir.file("c")}), "");
  EXPECT_NE(mergeError({f.dir.file("a"), f.dir.file("b"), f.dir.file("c"), f.dir.file("c")}).find("given twice"),
            std::string::npos);
  // The same shard again under another split.
  f.write(1, 2, "d");
  EXPECT_NE(mergeError({f.dir.file("a"), f.dir.file("b"), f.dir.file("c"), f.dir.file("d")}).find("shards"),
            std::string::npos);
  // Another study's shard.
  FakeShards other("other");
  other.write(3, 3, "c");
  EXPECT_NE(mergeError({f.dir.file("a"), f.dir.file("b"), other.dir.file("c")}).find("another study"),
            std::string::npos);
  EXPECT_NE(mergeError({f.dir.file("nothing")}).find("not a folder"), std::string::npos);
  // A shard is never overwritten.
  EXPECT_THROW(f.write(1, 3, "a"), InputError);
}

std::string runCli(const std::string& args, const test::TempDir& dir, int* code = nullptr) {
  const test::CommandOutput r = test::runCommandWithStderr(std::string(COLOSIM_EXE) + " " + args, dir);
  if (code) *code = r.code;
  else EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
  return r.out;
}

TEST(StudyRun, SeedZeroCaseEqualsColosimRun) {
  test::TempDir dir;
  const Study s = parseStudy(tinyStudyText(2.6), dir.write("s.json", tinyStudyText(2.6)));
  const CaseResult c = runStudyCase(s, studyCases(s)[0]);  // standard, sigmoid_push, scripted, seed 0
  const nlohmann::json run = nlohmann::json::parse(runCli("run sigmoid_push --duration 2.6 --score --json", dir));
  const std::vector<std::string>& names = studyMetricNames();
  auto metric = [&](const std::string& n) { return c.metrics[static_cast<size_t>(
                                                std::find(names.begin(), names.end(), n) - names.begin())]; };
  EXPECT_TRUE(run["time_to_caecum_s"].is_null());
  EXPECT_FALSE(metric("time_to_caecum_s"));
  EXPECT_EQ(*metric("caecal_intubation_rate"), 0.0);
  // The study's peak_wall_force_N is the whole scope's (the score's peak_wall_force_total_N).
  EXPECT_EQ(*metric("peak_wall_force_N"), run["peak_wall_force_total_N"].get<double>());
  for (const char* key : {"wall_force_integral_Ns", "peak_mesentery_stretch", "discomfort_index", "loop_time_s",
                          "loop_writhe_max", "peak_handle_force_N", "peak_handle_torque_Nm",
                          "shaft_movement_without_tip_progress_m"})
    EXPECT_EQ(*metric(key), run[key].get<double>()) << key;
  EXPECT_GT(*metric("peak_wall_force_N"), 0.0);
  EXPECT_GT(*metric("wall_force_integral_Ns"), 0.0);
}

TEST(StudyRun, ThreadCountsAndShardsGiveByteIdenticalOutput) {
  test::TempDir dir;
  const std::string study = dir.write("tiny.json", tinyStudyText(2.6));
  const std::string one = runCli("study " + study + " --json --threads 1", dir);
  // With a report too: gnuplot's messages stay out of stdout.
  const std::string two = runCli("study " + study + " --json --threads 2 --report " + dir.file("report"), dir);
  EXPECT_EQ(one, two);
  EXPECT_TRUE(std::filesystem::exists(dir.file("report/metrics.dat")));
  const nlohmann::json j = nlohmann::json::parse(one);
  EXPECT_EQ(j["study"], "tiny");
  ASSERT_EQ(j["designs"].size(), 2u);
  EXPECT_EQ(j["designs"][1]["name"], "stiff");
  EXPECT_EQ(j["designs"][1]["cases"], 4);
  // The stiffer shaft changes what the cases measure.
  EXPECT_NE(j["designs"][1]["vs_first"]["peak_wall_force_N"]["mean_difference"].get<double>(), 0.0);
  // Two shards on two "machines", merged: the same bytes.
  runCli("study " + study + " --shard 2/2 --out " + dir.file("b") + " --threads 1", dir);
  runCli("study " + study + " --shard 1/2 --out " + dir.file("a") + " --threads 1", dir);
  EXPECT_EQ(runCli("study --merge " + dir.file("a") + " " + dir.file("b") + " --json", dir), one);
  // A missing shard: a clear error, non-zero exit.
  int code = 0;
  runCli("study --merge " + dir.file("a") + " --json", dir, &code);
  EXPECT_EQ(code, 2);
}

// The report's files are what is tested, not the runs: 0.6 s of each case, the shapes at
// 0.5 s (the whole 2.6 s took a minute under the sanitizers).
TEST(StudyRun, ReportWritesDataAndScriptsOnlyInItsFolder) {
  test::TempDir dir;
  std::string text = tinyStudyText(0.6);
  replace(text, "\"seeds\": [0, 1]", "\"seeds\": [0]");
  replace(text, "\"scripted\", ", "");
  replace(text, "\"shape_times_s\": [2.5]", "\"shape_times_s\": [0.5]");
  const Study s = parseStudy(text, dir.write("s.json", text));
  const std::vector<StudyCase> cases = studyCases(s);
  const std::vector<CaseResult> results = runStudyCases(s, cases, 2);
  ASSERT_EQ(results[0].shapes_m.size(), 1u);
  EXPECT_FALSE(results[0].shapes_m[0].empty());
  EXPECT_FALSE(results[0].time_s.empty());
  const std::string report = dir.file("report");
  writeStudyReport(s, cases, results, report);
  for (const char* f : {"metrics.dat", "distributions.gp", "forces.gp", "shapes.gp", "timeline_standard.dat",
                        "timeline_stiff.dat", "shape_standard_t0.5.dat"})
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(report) / f)) << f;
  const std::string metrics = test::readFile(report + "/metrics.dat");
  EXPECT_NE(metrics.find("lumen_following"), std::string::npos);
}

}  // namespace
}  // namespace colosim
