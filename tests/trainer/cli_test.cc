// Drives the real `colosim` executable: exit codes and messages users and scripts see.
#include <array>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixture.h"

namespace {

using Result = colosim::test::CommandResult;

// stdout and stderr together.
Result run(const std::string& args) {
  return colosim::test::runCommand(std::string(COLOSIM_EXE) + " " + args + " 2>&1");
}

TEST(Cli, HelpWorksEverywhere) {
  EXPECT_EQ(run("--help").code, 0);
  EXPECT_EQ(run("run --help").code, 0);
  EXPECT_EQ(run("bench --help").code, 0);
}

TEST(Cli, RunSettlesAndSummarises) {
  const Result r = run("run --duration 0.2");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("energy at end"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max displacement"), std::string::npos);
  EXPECT_NE(r.out.find("time per step"), std::string::npos);
}

TEST(Cli, BadParameterFileExitsWithTwoAndNamesIt) {
  colosim::test::TempDir dir;
  const std::string f = dir.write("bad.json", "{\"format\": \"colosim-params\", \"version\": 1, \"colon\": 3}");
  const Result r = run("run --duration 0.1 --params " + f);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(f), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("colon"), std::string::npos) << r.out;
}

// --threads 2 runs each step's halves on two threads: the scores are the same bytes, and
// the option is refused where it does not apply.
TEST(Cli, RunOnTwoThreadsGivesTheSameScores) {
  const Result one = run("run sigmoid_untwist --duration 2.5 --score --json");
  const Result two = run("run sigmoid_untwist --duration 2.5 --score --json --threads 2");
  ASSERT_EQ(one.code, 0) << one.out;
  ASSERT_EQ(two.code, 0) << two.out;
  EXPECT_GT(nlohmann::json::parse(one.out)["peak_handle_force_N"].get<double>(), 0.0);
  EXPECT_EQ(one.out, two.out);
  EXPECT_EQ(run("run sigmoid_untwist --duration 0.1 --threads 3").code, 2);
  const Result settle = run("run --duration 0.1 --threads 2");
  EXPECT_EQ(settle.code, 2) << settle.out;
  EXPECT_NE(settle.out.find("--threads"), std::string::npos) << settle.out;
}

TEST(Cli, UnknownBenchmarkAndBadFlagsExitWithTwo) {
  EXPECT_EQ(run("bench no_such_bench").code, 2);
  EXPECT_EQ(run("run --duration -1").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
}

// The endurance benchmark, short (1.8 s simulated; the hour is run by hand, README):
// finite, bounded energy, no limiter at its clinical pace, memory figures read, and
// --hours refused where it does not apply.
TEST(Cli, BenchEnduranceShortRunStaysBounded) {
  const Result r = run("bench endurance --json --hours 0.0005");
  ASSERT_EQ(r.code, 0) << r.out;
  const size_t brace = r.out.find("\n{");
  ASSERT_NE(brace, std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out.substr(brace + 1));
  EXPECT_EQ(j["steps"], 1800);
  EXPECT_TRUE(j["finite"].get<bool>());
  EXPECT_EQ(j["solver_limited_steps"], 0);
  EXPECT_EQ(j["windows"].size(), 4u);
  // Bounded: the colon and scope hold well under 1 J (gravity from the origin, elastic, kinetic).
  EXPECT_LT(j["energy_max_J"].get<double>(), 1.0);
  EXPECT_GT(j["energy_min_J"].get<double>(), -1.0);
  EXPECT_LT(j["kinetic_max_J"].get<double>(), 0.2);
  EXPECT_GT(j["rss_kB_end"].get<long>(), 0);
  EXPECT_GE(j["hwm_kB_end"].get<long>(), j["rss_kB_end"].get<long>());
  EXPECT_GT(j["steps_per_s"].get<double>(), 0);
  EXPECT_EQ(run("bench colon --hours 1").code, 2);
  EXPECT_EQ(run("bench endurance --hours 0").code, 2);
}

}  // namespace
