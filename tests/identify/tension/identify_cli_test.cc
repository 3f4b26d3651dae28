// `colosim identify` and `colosim run --tension-law`, driven as users drive them, and the
// shipped example data.
#include <array>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "identify/tension/synthetic.h"
#include "fixture.h"

namespace {

using Result = colosim::test::CommandResult;

// stdout, and stderr too when asked.
Result run(const std::string& args, bool with_stderr = true) {
  return colosim::test::runCommand(std::string(COLOSIM_EXE) + " " + args + (with_stderr ? " 2>&1" : " 2>/dev/null"));
}

const std::string kSample1 = colosim::test::asset("measurements/tension_fig8_sample1.csv");

TEST(IdentifyCli, ShippedDataIsWhatTheGeneratorWrites) {
  for (int sample = 1; sample <= 2; ++sample) {
    colosim::TensionTest t = colosim::generateTensionTest(colosim::shippedSampleSpec(sample));
    t.metadata.insert(t.metadata.begin(), {"note", "SYNTHETIC data shaped like Kuehl & Dumont's Figure 8 (sample " +
                                                       std::to_string(sample) +
                                                       " of 2, pig colon, 180 mm, stretched to 0.12 m), not a measurement"});
    colosim::test::TempDir dir;
    colosim::writeTensionTest(dir.file("s.csv"), t);
    const std::string shipped =
        colosim::test::asset("measurements/tension_fig8_sample" + std::to_string(sample) + ".csv");
    EXPECT_EQ(colosim::test::readFile(dir.file("s.csv")), colosim::test::readFile(shipped)) << shipped;
    // Figure 8's shape: stretched to 0.12 m, about 10-12 N at the top.
    double emax = 0, fmax = 0;
    for (size_t k = 0; k < t.rows(); ++k) emax = std::max(emax, t.elongation_m[k]), fmax = std::max(fmax, t.force_N[k]);
    EXPECT_NEAR(emax, 0.12, 0.002);
    EXPECT_GT(fmax, 9.5);
    EXPECT_LT(fmax, 12.5);
  }
}

TEST(IdentifyCli, JsonHasTheDocumentedKeysAndFindsTheShippedEffects) {
  const Result r = run("identify " + kSample1 + " --json", false);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"effects", "baseline", "extended", "gain", "unexplained", "evidence"})
    EXPECT_TRUE(j.contains(key)) << key;
  for (const char* m : {"baseline", "extended"})
    for (const char* key : {"law", "params", "rmse_N", "heldout_rmse_N"}) EXPECT_TRUE(j[m].contains(key)) << m << key;
  EXPECT_EQ(j["baseline"]["law"], "voigt");
  EXPECT_EQ(j["extended"]["law"], "extended");
  const std::set<std::string> found = j["effects"].get<std::set<std::string>>();
  EXPECT_EQ(found, (std::set<std::string>{"strain_stiffening", "stress_relaxation"}));
  EXPECT_GT(j["gain"]["heldout_rmse_ratio"].get<double>(), 2.0);
  EXPECT_FALSE(j["unexplained"].get<bool>());
  EXPECT_FALSE(j["evidence"]["candidates"].empty());
}

TEST(IdentifyCli, LawOutRunsInTheColonAndReportWritesPlots) {
  colosim::test::TempDir dir;
  const std::string law = dir.file("law.json"), report = dir.file("report");
  const Result r = run("identify " + kSample1 + " --law-out " + law + " --report " + report);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("Cause:"), std::string::npos) << r.out;
  for (const char* f : {"force_time.png", "force_elongation.png", "residuals.png", "diagnosis.txt", "identify.json"})
    EXPECT_GT(std::filesystem::file_size(report + "/" + f), 100u) << f;
  EXPECT_EQ(colosim::test::readFile(report + "/force_time.png").substr(1, 3), "PNG");
  const Result run_law = run("run settle --duration 0.5 --tension-law " + law);
  EXPECT_EQ(run_law.code, 0) << run_law.out;
  EXPECT_NE(run_law.out.find("tension law          extended"), std::string::npos) << run_law.out;
  EXPECT_NE(run_law.out.find("fung_b"), std::string::npos) << run_law.out;
}

TEST(IdentifyCli, BadInputExitsTwoNamesTheLineAndWritesNothing) {
  colosim::test::TempDir dir;
  std::string text = colosim::test::readFile(kSample1);
  const size_t nan_at = text.find('\n', text.find("time_s,elongation_m,force_N") + 40) + 1;
  text = text.substr(0, nan_at) + "1000.0,nan,0.1\n" + text.substr(nan_at);
  const std::string bad = dir.write("bad.csv", text);
  const std::string law = dir.file("law.json"), report = dir.file("report");
  colosim::test::TempDir keep;
  const std::string existing = keep.write("law.json", "precious");
  Result r = run("identify " + bad + " --json --law-out " + existing + " --report " + report);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(bad + ":"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("not finite"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(report));
  EXPECT_EQ(colosim::test::readFile(existing), "precious");
  EXPECT_EQ(run("identify " + dir.file("missing.csv")).code, 2);
}

TEST(IdentifyCli, BadLawFilesExitTwoNamingTheKey) {
  colosim::test::TempDir dir;
  const std::string good =
      R"({"format": "colosim-tension-law v1", "law": "extended", "effects": ["strain_stiffening"],
          "params": {"EA_N": {"value": 6, "unit": "N"}, "EC_Ns": {"value": 0.05, "unit": "N s"},
                     "fung_b": {"value": 2.5, "unit": "1"}}, "source": "test"})";
  EXPECT_EQ(run("run --duration 0.01 --tension-law " + dir.write("good.json", good)).code, 0);
  struct Bad {
    std::string from, to, what;
  };
  const std::vector<Bad> bads = {
      {"\"N s\"", "\"N/s\"", "params.EC_Ns.unit"},
      {"\"strain_stiffening\"", "\"creep\"", "effects[0]"},
      {"\"fung_b\"", "\"fung_c\"", "params.fung_b"},
      {"\"value\": 6,", "\"value\": -6,", "EA_N"},
      {"\"law\": \"extended\"", "\"law\": \"voigt\"", "law"},
      {"\"format\": \"colosim-tension-law v1\",", "", "format"},
      {"\"source\": \"test\"", "\"source\": \"test\", \"extra\": 1", "extra"},
  };
  for (const Bad& b : bads) {
    std::string text = good;
    text.replace(text.find(b.from), b.from.size(), b.to);
    const std::string path = dir.write("bad.json", text);
    const Result r = run("run --duration 0.01 --tension-law " + path);
    EXPECT_EQ(r.code, 2) << b.what << ": " << r.out;
    EXPECT_NE(r.out.find(path), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(b.what), std::string::npos) << b.what << ": " << r.out;
  }
}

TEST(IdentifyCli, ARatchetingSetIsReadFromItsLawFileAndOutOfRangeNamed) {
  colosim::test::TempDir dir;
  const std::string law =
      R"({"format": "colosim-tension-law v1", "law": "extended", "effects": ["permanent_set"],
          "params": {"EA_N": {"value": 6, "unit": "N"}, "EC_Ns": {"value": 0.05, "unit": "N s"},
                     "set_ratio": {"value": 0.1, "unit": "1"}, "set_yield_strain": {"value": 0.05, "unit": "1"},
                     "set_ratchet": {"value": 0.04, "unit": "1"}}})";
  const Result r = run("run --duration 0.01 --tension-law " + dir.write("ratchet.json", law));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("set_ratchet"), std::string::npos) << r.out;
  std::string bad = law;
  bad.replace(bad.find("0.04"), 4, "1.5");
  const std::string path = dir.write("bad_ratchet.json", bad);
  const Result b = run("run --duration 0.01 --tension-law " + path);
  EXPECT_EQ(b.code, 2) << b.out;
  EXPECT_NE(b.out.find(path), std::string::npos) << b.out;
  EXPECT_NE(b.out.find("set_ratchet"), std::string::npos) << b.out;
}

}  // namespace
