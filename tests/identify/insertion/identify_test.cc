// Identification at the organ level on short synthetic recordings (4-6 s, coarse model):
// an effect hidden with a random magnitude and protocol (seeded) must be named with a
// held-out gain; a recording with no effect must give the empty answer.
// cyclic_softening is tested on its own protocol, three insert / withdraw cycles in 6 s that
// stretch and relieve the sigmoid again and again: softening is named there (4 of 5 seeds
// tried, the miss an empty answer; docs/organ-identification.md), and the same protocol with
// nothing hidden must give the empty answer. On the 4 s push-hold-pull-push protocol one seed
// (105, d_inf 0.34) left it at 1.1 times the noise, nothing named; not tried over seeds.
// strain_stiffening and stress_relaxation are tested on a 3 s staircase from 40-50 cm (two quick
// pushes of 4-7 cm, each held 1.2 s): the colon is stretched there (from 10-18 cm it hardly is,
// the force change 0.03-0.4 times the noise) and relaxation shows in the holds; named on every
// seed tried (docs/organ-identification.md), and the staircase with nothing hidden must give the
// empty answer.
#include "identify/insertion/identify.h"

#include <algorithm>
#include <thread>

#include <gtest/gtest.h>

#include "identify/insertion/synthetic.h"

namespace colosim {
namespace {

struct Case {
  int effect_index;  // -1: none
  uint64_t seed;
  int cycles = 0;            // > 0: insert / withdraw cycles (synthetic_insertion.h)
  double duration_s = 4.0;   // [s]
  int holds = 0;             // > 0 (cycles 0): push-and-hold stages (synthetic_insertion.h)
};

class HiddenOrganEffect : public ::testing::TestWithParam<Case> {};

TEST_P(HiddenOrganEffect, IsNamedWithAHeldOutGainOrTheAnswerIsEmpty) {
  const Case c = GetParam();
  const ReplaySetup setup = makeReplaySetup(findScenario("free_insertion_attached_rectum"), 0.03);
  const SyntheticInsertionSpec spec = drawSyntheticInsertion(c.seed, c.effect_index, c.duration_s, c.cycles, c.holds);
  const InsertionRecording rec = makeSyntheticInsertion(setup, spec);
  const InsertionIdentifyResult r = identifyInsertion(rec, setup);
  std::printf("hidden %s %.4g: found [%s], gain %.2f, %d simulations, %.1f s\n",
              spec.effect.empty() ? "none" : spec.effect.c_str(), spec.value,
              r.effects.empty() ? "" : r.effects.front().c_str(), r.heldout_rmse_ratio, r.simulations, r.seconds);
  if (spec.effect.empty()) {
    EXPECT_TRUE(r.effects.empty()) << r.diagnosis;
    EXPECT_FALSE(r.unexplained) << r.diagnosis;
  } else {
    ASSERT_FALSE(r.effects.empty()) << r.diagnosis;
    EXPECT_EQ(r.effects.front(), spec.effect) << r.diagnosis;
    EXPECT_GT(r.heldout_rmse_ratio, 1.05) << r.diagnosis;
  }
}

INSTANTIATE_TEST_SUITE_P(Organ, HiddenOrganEffect,
                         ::testing::Values(Case{-1, 101}, Case{0, 102}, Case{1, 103}, Case{2, 104}, Case{6, 106},
                                           Case{5, 107, 3, 6.0}, Case{-1, 101, 3, 6.0},
                                           Case{3, 201, 0, 3.0, 2}, Case{4, 204, 0, 3.0, 2}, Case{-1, 203, 0, 3.0, 2}),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           return (i.param.effect_index < 0 ? std::string("none")
                                                            : organEffectNames()[i.param.effect_index]) +
                                  (i.param.cycles > 0 ? "_cycles" : i.param.holds > 0 ? "_holds" : "");
                         });

TEST(OrganIdentify, AReplayOnAnotherThreadIsBitIdentical) {
  // The search runs replays on two threads: each must not depend on where it runs.
  const ReplaySetup setup = makeReplaySetup(findScenario("free_insertion_attached_rectum"), 0.03);
  const InsertionRecording rec = makeSyntheticInsertion(setup, drawSyntheticInsertion(7, 0, 0.5));
  OrganParams p;
  p.friction = 0.2;
  p.bending_EI_Nm2 = 0.02;
  const Prediction a = replayInsertion(setup, rec, p);
  Prediction b;
  std::thread t([&] { b = replayInsertion(setup, rec, p); });
  t.join();
  EXPECT_EQ(a.force_N, b.force_N);
  EXPECT_EQ(a.torque_Nm, b.torque_Nm);
}

}  // namespace
}  // namespace colosim

namespace colosim {
namespace {

// One held-out measure (issue 17): an effect whose reported held-out gain is at or below 1
// is not named, and the data are reported unexplained.
TEST(OrganIdentify, NeverNamesAnEffectWhoseHeldOutGainIsNotAboveOne) {
  InsertionIdentifyResult r;
  r.baseline.heldout_rmse_N = 0.20;
  r.baseline.rmse_N = 0.19;
  r.extended.effects = {"wall_friction"};
  r.extended.params.friction = 0.2;
  for (double gain : {0.93, 1.0}) {
    InsertionIdentifyResult x = r;
    x.effects = {"wall_friction"};
    x.extended.heldout_rmse_N = 0.20 / gain;
    x.heldout_rmse_ratio = gain;
    refuteUnconfirmedGain(&x);
    EXPECT_TRUE(x.effects.empty()) << gain;
    EXPECT_EQ(x.refuted_effects, std::vector<std::string>{"wall_friction"});
    EXPECT_EQ(x.refuted_heldout_rmse_ratio, gain);
    EXPECT_EQ(x.heldout_rmse_ratio, 1.0);
    EXPECT_EQ(x.extended.params.friction, 0.0);  // the paper's model is reported
    EXPECT_EQ(x.extended.heldout_rmse_N, 0.20);
  }
  InsertionIdentifyResult kept = r;
  kept.effects = {"wall_friction"};
  kept.extended.heldout_rmse_N = 0.19;
  kept.heldout_rmse_ratio = 0.20 / 0.19;
  refuteUnconfirmedGain(&kept);
  EXPECT_EQ(kept.effects, std::vector<std::string>{"wall_friction"});
  EXPECT_TRUE(kept.refuted_effects.empty());
}

// Data made at the parameter file's 1.5 cm, twice as fine as the 3 cm search, on the
// two-rate protocol (not one of the cases above): with nothing hidden the paper's model
// fits to the noise (RMSE under 1.5 times the sensor's) and nothing is named.
TEST(OrganIdentify, FineDataWithNothingHiddenFitToTheNoise) {
  const ReplaySetup fine = makeReplaySetup(findScenario("free_insertion_attached_rectum"));
  ASSERT_EQ(fine.params.colon.control_point_spacing_m, 0.015);
  const SyntheticInsertionSpec spec = drawTwoRateInsertion(301, -1, 2.0);
  const InsertionRecording rec = makeSyntheticInsertion(fine, spec);
  const InsertionIdentifyResult r = identifyInsertion(rec, fine);
  std::printf("%s", r.diagnosis.c_str());
  EXPECT_EQ(r.data_spacing_m, 0.015);
  EXPECT_EQ(r.search_spacing_m, 0.03);
  EXPECT_GT(r.mismatch_rms_N, 0.0);
  EXPECT_TRUE(r.effects.empty()) << r.diagnosis;
  EXPECT_FALSE(r.unexplained) << r.diagnosis;
  EXPECT_LT(r.baseline.rmse_N, 1.5 * spec.force_noise_N) << r.diagnosis;
}

// The refinement's fallback (the search's leaders leave structure, so every candidate is
// searched at the data's resolution) must reach a magnitude the search never saw. Trial case
// cyclic_softening, seed 1003 of tools/organ_trials (two-rate protocol, 2 s, made at 1.5 cm,
// d_inf 0.41 hidden): the coarse search chose nothing, and a fallback that started softening
// from one grid value (0.06-0.24) found its best at 0 and named permanent_set instead.
// Since the wires and the backed wall of session 15 that case is settled without the
// fallback; seed 1002 (d_inf 0.42) goes through it (seeds 1001-1005: the fallback in 1002
// and 1004, softening named in all five).
TEST(OrganIdentify, TheFallbackSearchesEveryCandidateFromItsWholeGrid) {
  const ReplaySetup fine = makeReplaySetup(findScenario("free_insertion_attached_rectum"));
  const std::vector<std::string>& names = organEffectNames();
  const int softening = static_cast<int>(std::find(names.begin(), names.end(), "cyclic_softening") - names.begin());
  ASSERT_LT(softening, static_cast<int>(names.size()));
  const SyntheticInsertionSpec spec = drawTwoRateInsertion(1002, softening, 2.0);
  const InsertionRecording rec = makeSyntheticInsertion(fine, spec);
  InsertionIdentifyOptions opt;
  opt.threads = 2;
  const InsertionIdentifyResult r = identifyInsertion(rec, fine, opt);
  std::printf("%s", r.diagnosis.c_str());
  EXPECT_TRUE(r.fine_all_candidates) << "the case no longer goes through the fallback: choose another";
  ASSERT_FALSE(r.effects.empty()) << r.diagnosis;
  EXPECT_EQ(r.effects.front(), "cyclic_softening") << r.diagnosis;
  EXPECT_NEAR(organEffectValue(r.extended.params, "cyclic_softening"), spec.value, 0.15 * spec.value) << r.diagnosis;
  EXPECT_GT(r.heldout_rmse_ratio, 1.0);
}

}  // namespace
}  // namespace colosim

namespace colosim {
namespace {

// Round 2 judged on round 1's leaders refined at the data's resolution (the search's own
// residual keeps the coarse model's mismatch, so it alone would run round 2 for nothing) must
// change no answer: the same effects and magnitudes, bit for bit, with fewer replays. Data at
// 3 cm, search at 6 cm (the same relation as the shipped 1.5 cm and 3 cm, at a quarter of the
// cost), 10 s of the shipped recording's protocol: there the search chooses colon_bending and
// its residual stays 10 times the noise, while at 3 cm the same effect leaves the noise
// (107 replays against 184). Shorter recordings of it (6, 8 s) leave the search choosing
// nothing, where round 2 is not reached at all.
// The same case checks the refinement's other shortcut: the search's choice is refined first,
// and once it is at the noise the other leaders are not refined; that too changes no answer.
void expectTheSameAnswer(const InsertionIdentifyResult& a, const InsertionIdentifyResult& b) {
  EXPECT_EQ(a.effects, b.effects);
  for (const std::string& e : organEffectNames())
    EXPECT_EQ(organEffectValue(a.extended.params, e), organEffectValue(b.extended.params, e)) << e;
  EXPECT_EQ(a.extended.heldout_rmse_N, b.extended.heldout_rmse_N);
  EXPECT_EQ(a.heldout_rmse_ratio, b.heldout_rmse_ratio);
  EXPECT_EQ(a.unexplained, b.unexplained);
}

TEST(OrganIdentify, Round2JudgedAtTheDataResolutionChangesNoAnswer) {
  const ReplaySetup data = makeReplaySetup(findScenario("free_insertion_attached_rectum"), 0.03);
  const SyntheticInsertionSpec spec = drawSyntheticInsertion(2026, 1, 10.0);  // colon_bending, the shipped draws
  const InsertionRecording rec = makeSyntheticInsertion(data, spec);
  InsertionIdentifyOptions opt;
  opt.threads = 2;
  opt.search_spacing_m = 0.06;
  const InsertionIdentifyResult judged = identifyInsertion(rec, data, opt);
  opt.judge_rounds_at_data_resolution = false;
  const InsertionIdentifyResult searched = identifyInsertion(rec, data, opt);
  std::printf("%s\n%s", judged.diagnosis.c_str(), searched.diagnosis.c_str());
  EXPECT_EQ(judged.skipped_round, 2) << judged.diagnosis;
  EXPECT_TRUE(judged.skipped_at_data_resolution);
  EXPECT_EQ(searched.skipped_round, 0) << searched.diagnosis;
  EXPECT_LT(judged.simulations, searched.simulations);
  expectTheSameAnswer(judged, searched);
  // The search steps at 2 ms, the data's model at 1 ms (6 cm against 3 cm).
  EXPECT_EQ(judged.search_dt_s, 2 * data.dt_s);

  opt.judge_rounds_at_data_resolution = true;
  opt.refine_choice_first = false;
  const InsertionIdentifyResult every = identifyInsertion(rec, data, opt);
  std::printf("%s", every.diagnosis.c_str());
  EXPECT_FALSE(judged.leaders_not_refined.empty()) << judged.diagnosis;
  EXPECT_TRUE(every.leaders_not_refined.empty());
  EXPECT_LT(judged.fine_simulations, every.fine_simulations);
  expectTheSameAnswer(judged, every);

  // Guessing the refinement's next replays on a free thread changes no answer and no count.
  opt.refine_choice_first = true;
  opt.guess_next_replays = false;
  const InsertionIdentifyResult unguessed = identifyInsertion(rec, data, opt);
  EXPECT_EQ(unguessed.guessed_replays, 0);
  EXPECT_EQ(unguessed.simulations, judged.simulations);
  EXPECT_EQ(unguessed.fine_simulations, judged.fine_simulations);
  expectTheSameAnswer(judged, unguessed);
}

}  // namespace
}  // namespace colosim
