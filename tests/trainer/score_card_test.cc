// The trainer's score card (trainer/score_card.h) and the scope-shape inset
// (trainer/scope_inset.h): bands at their stated thresholds, the coronal projection. The
// shipped expert sessions the card compares with: tests/trainer/session_report_test.cc.
#include "trainer/score_card.h"

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "fixture.h"
#include "trainer/scope_inset.h"

namespace colosim {
namespace {

const ScoreCardRow& row(const std::vector<ScoreCardRow>& rows, const std::string& key) {
  for (const ScoreCardRow& r : rows)
    if (r.key == key) return r;
  throw std::runtime_error("no row " + key);
}

TEST(ScoreCard, RelativeBandsAtTheirThresholds) {
  const nlohmann::json e({{"peak_push_N", 10.0}, {"excessive_pressure_episodes", 0},
                                        {"lumen_visible_pct", 80.0}, {"time_to_caecum_s", nullptr}});
  auto band = [&](const std::string& key, double v) {
    return row(scoreCard(nlohmann::json{{key, v}}, &e), key).band;
  };
  // Lower is better: green <= 1.25 E (12.5 N), amber <= 2 E (20 N), red beyond.
  EXPECT_EQ(band("peak_push_N", 12.5), "green");
  EXPECT_EQ(band("peak_push_N", 12.6), "amber");
  EXPECT_EQ(band("peak_push_N", 20.0), "amber");
  EXPECT_EQ(band("peak_push_N", 20.1), "red");
  // An expert's 0: the slack (1 episode) keeps one episode green, three red.
  EXPECT_EQ(band("excessive_pressure_episodes", 1), "green");
  EXPECT_EQ(band("excessive_pressure_episodes", 2), "amber");
  EXPECT_EQ(band("excessive_pressure_episodes", 3), "red");
  // Higher is better: within 10 points green, 25 amber.
  EXPECT_EQ(band("lumen_visible_pct", 70.0), "green");
  EXPECT_EQ(band("lumen_visible_pct", 69.0), "amber");
  EXPECT_EQ(band("lumen_visible_pct", 54.0), "red");
  // No expert: no band, the value still shown.
  const std::vector<ScoreCardRow> alone = scoreCard(nlohmann::json{{"peak_push_N", 30.0}}, nullptr);
  EXPECT_EQ(row(alone, "peak_push_N").band, "none");
  EXPECT_EQ(*row(alone, "peak_push_N").value, 30.0);
  EXPECT_FALSE(row(alone, "peak_push_N").expert);
  // A score that is not measured (null) has no band.
  EXPECT_EQ(row(scoreCard(nlohmann::json{{"lumen_visible_pct", nullptr}}, &e), "lumen_visible_pct").band, "none");
}

TEST(ScoreCard, CaecumBandsAreClinicalAndOnlyWhereTheExpertGoesThere) {
  const nlohmann::json to_caecum({{"time_to_caecum_s", 201.4}});
  auto time_band = [&](const nlohmann::json& t) {
    return row(scoreCard(nlohmann::json{{"time_to_caecum_s", t}}, &to_caecum), "time_to_caecum_s").band;
  };
  EXPECT_EQ(time_band(959.0), "green");    // < 16 min
  EXPECT_EQ(time_band(960.0), "amber");    // 16-20 min
  EXPECT_EQ(time_band(1199.0), "amber");
  EXPECT_EQ(time_band(1200.0), "red");
  EXPECT_EQ(time_band(nullptr), "red");    // not reached
  EXPECT_EQ(row(scoreCard(nlohmann::json{{"time_to_caecum_s", nullptr}}, &to_caecum), "caecum_reached").band, "red");
  EXPECT_EQ(row(scoreCard(nlohmann::json{{"time_to_caecum_s", 300.0}}, &to_caecum), "caecum_reached").band, "green");
  // The sigmoid experts stop at the splenic flexure: no caecum band.
  const nlohmann::json sigmoid({{"time_to_caecum_s", nullptr}});
  EXPECT_EQ(row(scoreCard(nlohmann::json{{"time_to_caecum_s", nullptr}}, &sigmoid), "caecum_reached").band, "none");
  EXPECT_EQ(formatCardValue("caecum_reached", 1.0), "yes");
  EXPECT_EQ(formatCardValue("time_to_caecum_s", 201.4), "201.4 (3.4 min)");
  EXPECT_EQ(formatCardValue("peak_push_N", std::nullopt), "-");
}

TEST(ScoreCard, JsonKeepsTheValuesAndWhatIsShown) {
  const nlohmann::json e({{"peak_wall_force_N", 8.7}});
  const nlohmann::json j = scoreCardJson(scoreCard(nlohmann::json{{"peak_wall_force_N", 34.9123}}, &e));
  bool found = false;
  for (const nlohmann::json& r : j)
    if (r["key"] == "peak_wall_force_N") {
      found = true;
      EXPECT_EQ(r["value"], 34.9123);
      EXPECT_EQ(r["expert"], 8.7);
      EXPECT_EQ(r["shown"], "34.9");
      EXPECT_EQ(r["unit"], "N");
      EXPECT_EQ(r["band"], "red");
      EXPECT_NE(r["rule"].get<std::string>().find("expert"), std::string::npos);
    }
  EXPECT_TRUE(found);
}

TEST(ScopeInset, CoronalProjectionKeepsLeftRightAndHeadUp) {
  // A colon box 0.3 m wide (x) and 0.4 m high (z): the frame for a square inset is square.
  Points q(3, 2);
  q.col(0) = Vec3(-0.15, 0.05, 0.0);
  q.col(1) = Vec3(0.15, -0.05, 0.4);
  const CoronalFrame f = coronalFrameFor(q, 1.0, 0.0);
  EXPECT_NEAR(f.x_max_m - f.x_min_m, f.z_max_m - f.z_min_m, 1e-12);
  EXPECT_NEAR(f.z_max_m - f.z_min_m, 0.4, 1e-12);
  EXPECT_NEAR(0.5 * (f.x_min_m + f.x_max_m), 0.0, 1e-12);
  // The patient's left (+x) to the image's right, cranial (+z) up; y (depth) dropped.
  const auto p = coronalInset({Vec3(0.1, 0.3, 0.3), Vec3(-0.1, -0.3, 0.1)}, f, 200.0f, 200.0f);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_NEAR(p[0][0], 150.0f, 1e-3);
  EXPECT_NEAR(p[0][1], 50.0f, 1e-3);
  EXPECT_NEAR(p[1][0], 50.0f, 1e-3);
  EXPECT_NEAR(p[1][1], 150.0f, 1e-3);
}

}  // namespace
}  // namespace colosim
