// `colosim score` and `colosim replay` end to end: exit codes, messages, JSON output.
// Sessions are recorded here with the colon + scope simulation (trainer/world_simulation.h),
// which is what the command simulates (app/cmd_score.cc: makeWorldSimulation).
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixture.h"
#include "session_fixture.h"
#include "trainer/world_simulation.h"
#include "trainer/colon_simulation.h"
#include "trainer/replay.h"

namespace colosim {
namespace {

using Result = test::CommandOutput;


std::string record(const test::TempDir& dir, const std::string& name, int seed) {
  std::string text = test::smallScenarioText(name);
  text.replace(text.find("\"seed\": 7"), 9, "\"seed\": " + std::to_string(seed));
  const Scenario sc = loadScenario(dir.write(name + ".json", text));
  const std::string path = dir.file(name + ".jsonl");
  WorldSimulation sim(sc);
  SessionWriter w(path, sessionHeaderFor(sc, "test"));
  runScenario(sc, sim, &w);
  return path;
}

TEST(SessionCli, HelpWorks) {
  test::TempDir dir;
  EXPECT_EQ(test::runColosim("score --help", dir).code, 0);
  EXPECT_EQ(test::runColosim("replay --help", dir).code, 0);
}

TEST(SessionCli, ReplayCheckReproducesTheRecording) {
  test::TempDir dir;
  const std::string s = record(dir, "a", 1);
  const Result r = test::runColosim("replay " + s + " --check", dir);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("matches the recording"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("250 steps"), std::string::npos) << r.out;

  // A recording whose final hash is not what the simulation gives: --check fails (exit 1).
  std::string text = test::readFile(s);
  const auto pos = text.rfind("\"state_hash\":\"") + 14;
  text[pos] = text[pos] == '0' ? '1' : '0';
  const std::string tampered = dir.write("tampered.jsonl", text);
  const Result t = test::runColosim("replay " + tampered + " --check", dir);
  EXPECT_EQ(t.code, 1) << t.out << t.err;
  EXPECT_NE(t.err.find("final state hash"), std::string::npos) << t.err;
  EXPECT_EQ(test::runColosim("replay " + tampered, dir).code, 0);  // without --check: reported, not failed
}

TEST(SessionCli, TruncatedSessionReplaysItsPrefixAndSaysSo) {
  test::TempDir dir;
  const std::string s = record(dir, "a", 1);
  const std::string text = test::readFile(s);
  const std::string cut = dir.write("cut.jsonl", text.substr(0, text.size() - 40));
  const Result r = test::runColosim("replay " + cut + " --check", dir);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("cut off"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("TRUNCATED"), std::string::npos) << r.out;
}

TEST(SessionCli, ScoreJsonIsOneObjectPerSessionInOrder) {
  test::TempDir dir;
  const std::string a = record(dir, "a", 1), b = record(dir, "b", 2), c = record(dir, "c", 3);
  const Result r = test::runColosim("score " + c + " " + a + " " + b + " --json", dir);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 3u);
  EXPECT_EQ(j[0]["session"], c);
  EXPECT_EQ(j[1]["session"], a);
  EXPECT_EQ(j[2]["session"], b);
  for (const nlohmann::json& o : j) {
    for (const char* key : {"time_to_caecum_s", "peak_handle_force_N", "peak_wall_force_N",
                            "excessive_pressure_episodes", "discomfort_index", "discomfort_time_pct",
                            "loop_time_s", "max_loop_turns", "mucosa_visualised_pct", "redout_time_s",
                            "lumen_lost_count", "insertion", "withdrawal", "units", "loop_writhe_max",
                            "region_length_ratio_min", "insertion_at_caecum_m"})
      EXPECT_TRUE(o.contains(key)) << key;
    EXPECT_TRUE(o["time_to_caecum_s"].is_null());  // the colon alone never reaches the caecum
    EXPECT_TRUE(o["insertion_at_caecum_m"].is_null());
    // The colon alone, hanging: every region within a few % of its rest length.
    ASSERT_TRUE(o["region_length_ratio_min"].contains("sigmoid")) << o["region_length_ratio_min"];
    for (const auto& [region, ratio] : o["region_length_ratio_min"].items())
      EXPECT_NEAR(ratio.get<double>(), 1.0, 0.05) << region;
    EXPECT_TRUE(o["state_hash_reproduced"].get<bool>());
    EXPECT_NEAR(o["duration_s"].get<double>(), 2.5, 1e-9);
  }
  // Text output too.
  const Result t = test::runColosim("score " + a, dir);
  EXPECT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("time to caecum"), std::string::npos) << t.out;
}

TEST(SessionCli, BadSessionsExitWithTwoNamingFileAndLine) {
  test::TempDir dir;
  const std::string good = record(dir, "a", 1);
  std::string text = test::readFile(good);
  text.replace(text.find("\"version\":1"), 11, "\"version\":2");
  const std::string bad = dir.write("bad.jsonl", text);
  const Result r = test::runColosim("score " + good + " " + bad + " --json", dir);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(bad + ":1:"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;  // nothing printed for the good one either
  EXPECT_EQ(test::runColosim("replay " + bad, dir).code, 2);
  EXPECT_EQ(test::runColosim("replay " + dir.file("none.jsonl"), dir).code, 2);

  // A session whose scenario has gone: exit 2 naming the session's header line.
  const std::string orphan = record(dir, "gone", 1);
  std::remove(dir.file("gone.json").c_str());
  const Result o = test::runColosim("replay " + orphan, dir);
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find(orphan + ":1:"), std::string::npos) << o.err;
}

TEST(SessionCli, FramesNeverOverwriteExistingFiles) {
  test::TempDir dir;
  const std::string s = record(dir, "a", 1);
  std::filesystem::create_directories(dir.file("frames"));
  const std::string keep = dir.write("frames/frame_000000.png", "precious");
  const Result r = test::runColosim("replay " + s + " --frames " + dir.file("frames"), dir);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("not empty"), std::string::npos) << r.err;
  EXPECT_EQ(test::readFile(keep), "precious");
  EXPECT_EQ(test::runColosim("replay " + s + " --size 10", dir).code, 2);
}

// A run with another parameter file (an identified model, `colosim run --params`) is
// recorded with that file named in the header, so the replay simulates the same model;
// what a session cannot name (--tension-law, the scan query) is refused with --record.
TEST(SessionCli, SessionRecordedWithAnotherParameterFileReplaysThatModel) {
  test::TempDir dir;
  const std::string scenario = dir.write("p.json", test::smallScenarioText("p"));
  nlohmann::json params = nlohmann::json::parse(test::readFile(std::string(COLOSIM_ASSET_DIR) + "/params/default.json"));
  params["contact"]["friction_coefficient"]["value"] = 0.6;
  const std::string sticky = dir.write("sticky.json", params.dump(2));

  const std::string with = dir.file("with.jsonl"), without = dir.file("without.jsonl");
  ASSERT_EQ(test::runColosim("run " + scenario + " --params " + sticky + " --record " + with, dir).code, 0);
  ASSERT_EQ(test::runColosim("run " + scenario + " --record " + without, dir).code, 0);
  const Session a = readSession(with), b = readSession(without);
  EXPECT_NE(a.header.params.find("sticky.json"), std::string::npos) << a.header.params;
  EXPECT_TRUE(b.header.params.empty());
  EXPECT_NE(a.final_state_hash, b.final_state_hash) << "the friction must change the motion";

  const Result r = test::runColosim("replay " + with + " --check", dir);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;

  // The file gone: the session cannot be replayed, said with its line.
  std::filesystem::rename(sticky, dir.file("moved.json"));
  const Result gone = test::runColosim("replay " + with, dir);
  EXPECT_EQ(gone.code, 2);
  EXPECT_NE(gone.err.find(with + ":1: params"), std::string::npos) << gone.err;

  for (const std::string& flag : {std::string("--query scan"), "--tension-law " + dir.file("law.json")}) {
    const std::string out = dir.file("refused.jsonl");
    const Result x = test::runColosim("run " + scenario + " " + flag + " --record " + out, dir);
    EXPECT_EQ(x.code, 2) << flag << ": " << x.err;
    EXPECT_NE(x.err.find("--record with"), std::string::npos) << x.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

}  // namespace
}  // namespace colosim
