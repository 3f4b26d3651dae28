// The scorer on synthetic telemetry whose scores are known exactly.
#include "trainer/score.h"
#include "step.h"

#include <cmath>
#include <functional>

#include <gtest/gtest.h>

namespace colosim {
namespace {

// Feeds `steps` records at 1 ms; `fill(k, t)` sets record k (time t already set).
void feed(Scorer& s, long steps, const std::function<void(long, Telemetry&)>& fill, long first = 0) {
  for (long k = first; k < first + steps; ++k) {
    Telemetry t;
    t.time_s = static_cast<double>(k + 1) * kDt;
    fill(k, t);
    s.add(t);
  }
}

int episodesFor(const std::vector<long>& runs, bool accumulate_time) {
  // Alternating runs above (6 N) and gaps below (1 N) the 5 N threshold, 100 steps apart.
  Scorer s;
  double time_s = 0;
  long k = 0;
  for (long run : runs) {
    for (int part = 0; part < 2; ++part) {
      const long n = part == 0 ? run : 100;
      for (long i = 0; i < n; ++i, ++k) {
        Telemetry t;
        time_s = accumulate_time ? time_s + kDt : static_cast<double>(k + 1) * kDt;
        t.time_s = time_s;
        t.wall_force_peak_N = part == 0 ? 6.0 : 1.0;
        s.add(t);
      }
    }
  }
  return s.json()["excessive_pressure_episodes"].get<int>();
}

TEST(Score, ExcessivePressureEpisodesNeedMoreThanHalfASecond) {
  for (bool accumulate : {false, true}) {
    SCOPED_TRACE(accumulate ? "time summed step by step" : "time k dt");
    EXPECT_EQ(episodesFor({500}, accumulate), 0);   // exactly 0.5 s: not more than 0.5 s
    EXPECT_EQ(episodesFor({499}, accumulate), 0);
    EXPECT_EQ(episodesFor({501}, accumulate), 1);   // 0.501 s
    EXPECT_EQ(episodesFor({3000}, accumulate), 1);  // one long episode counts once
    EXPECT_EQ(episodesFor({600, 400, 700, 501, 500}, accumulate), 3);
  }
  // The time above the threshold counts every step, episode or not.
  Scorer s;
  feed(s, 1000, [](long k, Telemetry& t) { t.wall_force_peak_N = k < 300 ? 7.0 : 0.0; });
  EXPECT_NEAR(s.json()["excessive_pressure_time_s"].get<double>(), 0.3, 1e-9);
  EXPECT_EQ(s.json()["peak_wall_force_N"].get<double>(), 7.0);
}

TEST(Score, RegionLengthRatioAndWritheKeepTheirExtremesPerPhase) {
  const std::vector<std::string> names = {"rectum", "sigmoid"};
  Scorer s;
  // The sigmoid shortens to 0.7 at 1 s and recovers; the rectum stretches (never below 1).
  // The writhe swings to -1.1 at 0.5 s. The caecum is reached at 1.5 s.
  feed(s, 2000, [&](long k, Telemetry& t) {
    const double time_s = (k + 1) * kDt;
    t.region_names = &names;
    t.region_length_ratio = {1.0 + 0.1 * time_s, 1.0 - 0.3 * std::exp(-std::pow((time_s - 1.0) / 0.1, 2))};
    t.loop_writhe = -1.1 * std::exp(-std::pow((time_s - 0.5) / 0.1, 2));
    t.tip_to_caecum_m = time_s < 1.5 ? 1.0 : 0.0;
  });
  const nlohmann::json j = s.json();
  EXPECT_NEAR(j["region_length_ratio_min"]["sigmoid"].get<double>(), 0.7, 1e-9);
  EXPECT_NEAR(j["region_length_ratio_min"]["rectum"].get<double>(), 1.0001, 1e-9);
  EXPECT_NEAR(j["loop_writhe_max"].get<double>(), 1.1, 1e-9);
  // Withdrawal (after 1.5 s) saw neither the loop nor the shortening.
  EXPECT_LT(j["withdrawal"]["loop_writhe_max"].get<double>(), 1e-6);
  EXPECT_GT(j["withdrawal"]["region_length_ratio_min"]["sigmoid"].get<double>(), 0.999);
  EXPECT_EQ(j["units"]["insertion_at_caecum_m"], "m");
}

TEST(Score, TimeToCaecumIsNullUntilReached) {
  Scorer never;
  feed(never, 2000, [](long, Telemetry& t) { t.tip_to_caecum_m = 0.031; });
  EXPECT_TRUE(never.json()["time_to_caecum_s"].is_null());
  EXPECT_TRUE(never.json()["withdrawal"].is_null());
  EXPECT_NEAR(never.json()["insertion"]["duration_s"].get<double>(), 2.0, 1e-9);

  EXPECT_TRUE(never.json()["insertion_at_caecum_m"].is_null());

  Scorer reached;
  // The tip closes in at 0.2 m/s from 1 m: within 3 cm at t = 4.85 s, while the scope goes
  // in at 0.25 m/s from 0.2 m: 0.2 + 0.25 * 4.85 = 1.4125 m inserted then (and more later).
  feed(reached, 6000, [](long k, Telemetry& t) {
    t.tip_to_caecum_m = std::max(0.0, 1.0 - 0.2 * (k + 1) * kDt);
    t.inserted_m = 0.2 + 0.25 * (k + 1) * kDt;
  });
  EXPECT_NEAR(reached.json()["time_to_caecum_s"].get<double>(), 4.85, 1.5e-3);
  EXPECT_NEAR(reached.json()["insertion_at_caecum_m"].get<double>(), 1.4125, 0.25 * 1.5e-3);

  // Times count from the end of a scripted set-up.
  ScoreOptions o;
  o.start_s = 2.0;
  Scorer late(o);
  feed(late, 6000, [](long k, Telemetry& t) { t.tip_to_caecum_m = std::max(0.0, 1.0 - 0.2 * (k + 1) * kDt); });
  EXPECT_NEAR(late.json()["time_to_caecum_s"].get<double>(), 2.85, 1.5e-3);
  EXPECT_NEAR(late.json()["duration_s"].get<double>(), 4.0, 1e-9);
}

TEST(Score, InsertionAndWithdrawalAreScoredSeparately) {
  Scorer s;
  // 3 s in at 10 N push, caecum reached at the end of second 3, then 2 s out at 4 N pull.
  feed(s, 5000, [](long k, Telemetry& t) {
    const bool in = k < 3000;
    t.handle_force_N = in ? 10.0 : -4.0;
    t.tip_to_caecum_m = k == 2999 ? 0.0 : 0.5;
    t.loop_turns = in ? 1.0 : 0.0;
  });
  const nlohmann::json j = s.json();
  EXPECT_NEAR(j["time_to_caecum_s"].get<double>(), 3.0, 1e-9);
  EXPECT_NEAR(j["insertion"]["duration_s"].get<double>(), 3.0, 1e-9);
  EXPECT_NEAR(j["withdrawal"]["duration_s"].get<double>(), 2.0, 1e-9);
  EXPECT_EQ(j["insertion"]["peak_handle_force_N"].get<double>(), 10.0);
  EXPECT_EQ(j["withdrawal"]["peak_handle_force_N"].get<double>(), 4.0);
  EXPECT_EQ(j["withdrawal"]["peak_pull_N"].get<double>(), 4.0);
  EXPECT_EQ(j["withdrawal"]["peak_push_N"].get<double>(), 0.0);
  EXPECT_EQ(j["peak_handle_force_N"].get<double>(), 10.0);
  EXPECT_EQ(j["peak_push_N"].get<double>(), 10.0);
  EXPECT_EQ(j["peak_pull_N"].get<double>(), 4.0);
  EXPECT_NEAR(j["handle_force_integral_Ns"].get<double>(), 3 * 10.0 + 2 * 4.0, 1e-6);
  EXPECT_NEAR(j["insertion"]["loop_time_s"].get<double>(), 3.0, 1e-9);
  EXPECT_NEAR(j["withdrawal"]["loop_time_s"].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(j["high_force_time_pct"].get<double>(), 0.0, 1e-9);  // 10 N is not above 10 N
}

TEST(Score, LoopsDiscomfortAndView) {
  Scorer s;
  // 5 s: a loop of 1.2 turns for the first 2 s, -0.7 (the other way) for 1 s, then 0.3;
  // the colon stretched 8 % (threshold 3 %) for the first 1.5 s, the mesentery stretched
  // 8 (threshold 5) for the first 2.5 s; the tip against the wall in [1 s, 1.25 s); the
  // lumen lost twice.
  feed(s, 5000, [](long k, Telemetry& t) {
    t.loop_turns = k < 2000 ? 1.2 : (k < 3000 ? -0.7 : 0.3);
    t.colon_stretch = k < 1500 ? 0.08 : 0.01;
    t.mesentery_stretch = k < 2500 ? 8.0 : 1.0;
    t.tip_against_wall = k >= 1000 && k < 1250;
    t.lumen_visible = !(k >= 1000 && k < 1300) && !(k >= 4000 && k < 4100);
  });
  const nlohmann::json j = s.json();
  EXPECT_NEAR(j["loop_time_s"].get<double>(), 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(j["max_loop_turns"].get<double>(), 1.2);
  EXPECT_NEAR(j["discomfort_index"].get<double>(), (0.08 - 0.03) * 1.5, 1e-9);
  EXPECT_NEAR(j["discomfort_time_pct"].get<double>(), 30.0, 1e-9);
  EXPECT_DOUBLE_EQ(j["peak_colon_stretch"].get<double>(), 0.08);
  EXPECT_DOUBLE_EQ(j["peak_mesentery_stretch"].get<double>(), 8.0);
  EXPECT_NEAR(j["mesentery_stretch_time_pct"].get<double>(), 50.0, 1e-9);
  EXPECT_NEAR(j["redout_time_s"].get<double>(), 0.25, 1e-9);
  EXPECT_EQ(j["lumen_lost_count"].get<int>(), 2);
  EXPECT_NEAR(j["lumen_visible_pct"].get<double>(), 100.0 * (5.0 - 0.4) / 5.0, 1e-9);
  // Units are given for every score.
  for (const char* key : {"peak_handle_force_N", "discomfort_index", "max_loop_turns", "mucosa_visualised_pct"})
    EXPECT_TRUE(j["units"].contains(key)) << key;
}

TEST(Score, MucosaVisualisedNeedsHalfASecondInTotal) {
  Scorer s;
  // 10 patches. Patches 0-4: seen 0.6 s each in one go. Patch 5: 0.4 s only.
  // Patch 6: twice 0.3 s (0.6 s in total: counts). Patch 7: 0.5 s exactly (counts).
  long k = 0;
  auto see = [&](int id, long steps) {
    feed(s, steps, [&](long, Telemetry& t) {
      t.patch_count = 10;
      t.patches_seen = {id, id};  // listed twice: counted once
    }, k);
    k += steps;
  };
  for (int id = 0; id < 5; ++id) see(id, 600);
  see(5, 400);
  see(6, 300);
  see(5, 0);
  see(6, 300);
  see(7, 500);
  EXPECT_NEAR(s.json()["mucosa_visualised_pct"].get<double>(), 70.0, 1e-9);
  // Not measured: null, not zero.
  Scorer none;
  feed(none, 10, [](long, Telemetry&) {});
  EXPECT_TRUE(none.json()["mucosa_visualised_pct"].is_null());
}

TEST(Score, PathsPerControl) {
  Scorer s;
  // The handle goes in 0.4 m while the tip moves only 0.1 m (a loop takes up the rest);
  // the rotation goes to 2 rad and back; a knob to 0.5 rad.
  feed(s, 1000, [](long k, Telemetry& t) {
    const double f = (k + 1) / 1000.0;
    t.input.insertion_m = 0.4 * f;
    t.tip_position_m = Vec3(0.1 * f, 0, 0);
    t.input.rotation_rad = k < 500 ? 4.0 * f : 4.0 * (1.0 - f);
    t.input.knob_updown_rad = 0.5 * f;
  });
  const nlohmann::json j = s.json();
  // Paths count from the first record on.
  EXPECT_NEAR(j["insertion_path_m"].get<double>(), 0.4 * 999 / 1000, 1e-9);
  EXPECT_NEAR(j["tip_path_m"].get<double>(), 0.1 * 999 / 1000, 1e-9);
  EXPECT_NEAR(j["tip_path_per_insertion_path"].get<double>(), 0.25, 1e-9);
  EXPECT_NEAR(j["rotation_path_rad"].get<double>(), 4.0, 0.01);
  EXPECT_NEAR(j["knob_path_rad"].get<double>(), 0.5 * 999 / 1000, 1e-9);
}

TEST(Score, SetUpBeforeTheStartIsNotScored) {
  ScoreOptions o;
  o.start_s = 1.0;
  Scorer s(o);
  feed(s, 3000, [](long k, Telemetry& t) { t.handle_force_N = k < 1000 ? 50.0 : 5.0; });
  EXPECT_EQ(s.json()["peak_handle_force_N"].get<double>(), 5.0);
  EXPECT_NEAR(s.json()["duration_s"].get<double>(), 2.0, 1e-9);
}

}  // namespace
}  // namespace colosim
