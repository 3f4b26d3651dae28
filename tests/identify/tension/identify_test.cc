// Statistical tests of the identification (identify/tension/identify.h): the seeded bench
// generator hides an effect (or none) in each case, with its parameters, protocol, noise,
// offset, actuator rounding, time-base jitter and slack drawn at random from physiological
// ranges; the identifier must name it.
#include "identify/tension/identify.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "identify/tension/synthetic.h"
#include "identify/tension/trial_bench.h"

namespace colosim {
namespace {

// Sized for the CI budget: ~2,300 rows per case (a 0.5 s sampling interval over ~19 min
// of protocol), 20 cases per class.
constexpr int kCases = 20;
constexpr double kDt = 0.5;

struct Case {
  SyntheticSpec spec;
  IdentifyResult result;
};

Case runCase(uint64_t seed, const std::vector<std::string>& effects) {
  SyntheticDraw draw;
  draw.effects = effects;
  draw.nominal_dt_s = kDt;
  Case c;
  c.spec = drawSyntheticSpec(seed, draw);
  c.result = identifyTension(generateTensionTest(c.spec));
  return c;
}

double param(const FittedModel& m, const std::string& name) {
  for (const ParamEstimate& p : m.params)
    if (p.name == name) return p.value;
  return NAN;
}

// The parameters that the protocol identifies for each effect (EC is not: at these rates
// its force is below the noise, see docs/identification.md).
std::vector<std::string> identifiable(const std::string& effect) {
  if (effect == "strain_stiffening") return {"EA_N", "fung_b"};
  if (effect == "stress_relaxation") return {"EA_N", "relax_g1", "relax_tau1_s"};
  if (effect == "cyclic_softening") return {"EA_N", "soften_d_inf", "soften_a_c"};
  if (effect == "permanent_set") return {"EA_N", "set_ratio"};
  return {"EA_N"};
}

class HiddenEffect : public ::testing::TestWithParam<std::string> {};

TEST_P(HiddenEffect, IsNamedItsParametersRecoveredAndTheGainMeasured) {
  const std::string effect = GetParam();
  const std::vector<std::string> truth = effect == "none" ? std::vector<std::string>{} : std::vector<std::string>{effect};
  const std::map<std::string, uint64_t> first_seed = {{"none", 1000}, {"strain_stiffening", 2000},
      {"stress_relaxation", 3000}, {"cyclic_softening", 4000}, {"permanent_set", 6000}};
  const uint64_t base = first_seed.at(effect);
  int right = 0, explained = 0, params_ok = 0;
  for (int k = 0; k < kCases; ++k) {
    const Case c = runCase(base + k, truth);
    const IdentifyResult& r = c.result;
    std::string got;
    for (const std::string& e : r.effects) got += e + " ";
    const bool named = r.effects == truth;
    right += named;
    explained += !r.unexplained;
    // A miss is reported; the requirement is the 95 % below.
    if (!named) std::printf("case %d (seed %lu): hidden [%s], found [%s]\n", k, static_cast<unsigned long>(base + k),
                            effect.c_str(), got.c_str());
    if (!truth.empty()) {
      // A held-out gain in every case with an effect.
      EXPECT_GT(r.heldout_rmse_ratio, 1.0) << "case " << k;
      EXPECT_LT(r.extended.heldout_rmse_N, r.baseline.heldout_rmse_N) << "case " << k;
    }
    if (!named) continue;
    // Recovered parameters within 10 %.
    const ExtendedTensionLaw true_law(c.spec.truth);
    bool ok = true;
    for (const std::string& name : identifiable(effect)) {
      double t = NAN;
      for (const LawParameter& p : true_law.parameters())
        if (p.name == name) t = p.value;
      const double f = param(r.extended, name);
      EXPECT_NEAR(f, t, 0.10 * std::abs(t)) << name << ", case " << k;
      ok = ok && std::abs(f - t) <= 0.10 * std::abs(t);
    }
    params_ok += ok;
  }
  // At least 95 % named right ("none": an empty list), and explained to the noise.
  EXPECT_GE(right, std::ceil(0.95 * kCases)) << effect;
  EXPECT_GE(explained, std::ceil(0.95 * kCases)) << effect;
  RecordProperty("named_right", right);
  RecordProperty("parameters_within_10_percent", params_ok);
  std::printf("%s: named right in %d / %d cases, parameters within 10 %% in %d\n", effect.c_str(), right, kCases,
              params_ok);
  // Every named case must have its identifiable parameters within 10 % (EXPECT_NEAR above).
}

INSTANTIATE_TEST_SUITE_P(Identify, HiddenEffect,
                         ::testing::Values("none", "strain_stiffening", "stress_relaxation", "cyclic_softening",
                                           "permanent_set"));

TEST(Identify, FindsTwoEffectsTogether) {
  // Every pair of effects, 4 cases each: both named (in either order) in >= 95 % of the
  // cases, and a held-out gain in every case.
  const std::vector<std::string>& names = tensionEffectNames();
  int both = 0, cases = 0;
  for (size_t a = 0; a < names.size(); ++a)
    for (size_t b = a + 1; b < names.size(); ++b)
      for (int k = 0; k < 4; ++k) {
        const Case c = runCase(5000 + 100 * cases + k, {names[a], names[b]});
        const std::set<std::string> found(c.result.effects.begin(), c.result.effects.end());
        const bool ok = found == std::set<std::string>{names[a], names[b]};
        both += ok;
        ++cases;
        if (!ok) {
          std::string got;
          for (const std::string& e : c.result.effects) got += e + " ";
          std::printf("hidden %s + %s, found [%s]\n", names[a].c_str(), names[b].c_str(), got.c_str());
        }
        EXPECT_GT(c.result.heldout_rmse_ratio, 1.0);
      }
  EXPECT_GE(both, std::ceil(0.95 * cases));
  std::printf("pairs: both effects named in %d / %d cases\n", both, cases);
}

TEST(Identify, SaysWhenStructureRemainsThatNoCandidateExplains) {
  // Dry friction in the grips is none of the candidate effects.
  int flagged = 0;
  constexpr int kForeignCases = 4;
  for (int k = 0; k < kForeignCases; ++k) {
    SyntheticDraw draw;
    draw.nominal_dt_s = kDt;
    SyntheticSpec spec = drawSyntheticSpec(7000 + k, draw);
    spec.foreign_friction_N = 0.4;
    const IdentifyResult r = identifyTension(generateTensionTest(spec));
    flagged += r.unexplained;
  }
  EXPECT_EQ(flagged, kForeignCases);
}

TEST(Identify, SameInputGivesBitIdenticalResults) {
  const Case a = runCase(42, {"stress_relaxation"});
  const Case b = runCase(42, {"stress_relaxation"});
  ASSERT_EQ(a.result.extended.params.size(), b.result.extended.params.size());
  for (size_t i = 0; i < a.result.extended.params.size(); ++i)
    EXPECT_EQ(a.result.extended.params[i].value, b.result.extended.params[i].value);
  EXPECT_EQ(a.result.extended.heldout_rmse_N, b.result.extended.heldout_rmse_N);
  EXPECT_EQ(a.result.effects, b.result.effects);
}

}  // namespace
}  // namespace colosim

namespace colosim {
namespace {

// One held-out measure (issue 17): `colosim identify` never names an effect whose reported
// held-out gain is at or below 1. The case is constructed: a rule that lets a candidate
// pay with any held-out ratio above 0.5 and any BIC makes the selection choose an effect on
// data of the Voigt law (each effect at its zero value is the Voigt law itself, so the best
// ratio is about 1). The test is small enough (~1,200 rows) that the selection's
// working set is every row, so the chosen candidate's ratio is the reported gain.
TEST(Identify, NeverNamesAnEffectWhoseHeldOutGainIsAtMostOne) {
  SyntheticDraw draw;
  draw.nominal_dt_s = 1.0;
  // White noise only: no effect can predict it (with this seed every candidate's held-out
  // ratio is below 1; the ASSERT below checks that the case is what it is meant to be).
  SyntheticSpec spec = drawSyntheticSpec(1024, draw);
  spec.coloured_sd_N = 0;
  const TensionTest test = generateTensionTest(spec);
  ASSERT_LT(test.rows(), 1500u);
  IdentifyOptions lax;
  lax.min_heldout_ratio = 0.5;
  lax.max_delta_bic = 1e9;
  lax.max_effects = 1;
  const IdentifyResult r = identifyTension(test, lax);
  // The selection chose a candidate whose held-out ratio is not above 1...
  const auto chosen = std::find_if(r.evidence.begin(), r.evidence.end(),
                                   [](const CandidateEvidence& e) { return e.chosen; });
  ASSERT_NE(chosen, r.evidence.end());
  ASSERT_LE(chosen->heldout_ratio, 1.0);
  // ...so nothing is named, the Voigt law is reported, and the data are unexplained.
  EXPECT_TRUE(r.effects.empty());
  EXPECT_EQ(r.refuted_effects, std::vector<std::string>{chosen->effect});
  EXPECT_LE(r.refuted_heldout_rmse_ratio, 1.0);
  EXPECT_EQ(r.heldout_rmse_ratio, 1.0);
  EXPECT_EQ(r.extended.lawName(), "voigt");
  EXPECT_TRUE(r.unexplained);
  EXPECT_NE(r.diagnosis.find("not a cause"), std::string::npos) << r.diagnosis;
  // The default rule names nothing on the same data.
  const IdentifyResult d = identifyTension(test);
  EXPECT_TRUE(d.effects.empty());
  EXPECT_TRUE(d.refuted_effects.empty());
}

// Whatever is named carries a reported held-out gain above 1, on a test large enough for
// the selection to run on a block-averaged working set (its split mapped onto every row).
TEST(Identify, ReportedGainOfANamedEffectIsAboveOne) {
  for (const char* effect : {"cyclic_softening", "permanent_set"}) {
    SyntheticDraw draw;
    draw.effects = {effect};
    draw.nominal_dt_s = 0.1;
    const IdentifyResult r = identifyTension(generateTensionTest(drawSyntheticSpec(4242, draw)));
    ASSERT_GT(r.working_rows, 0);
    EXPECT_EQ(r.effects, std::vector<std::string>{effect});
    EXPECT_GT(r.heldout_rmse_ratio, 1.0);
    EXPECT_LT(r.extended.heldout_rmse_N, r.baseline.heldout_rmse_N);
  }
}

}  // namespace
}  // namespace colosim

namespace colosim {
namespace {

// Forms other than the project generator's, from the trial bench (identify/tension/trial_bench.h,
// seeds apart from the trials' and their calibration's), where the law now has the form: a
// set with a yield strain and relaxation with two times. Each is named alone and its
// parameters are recovered within 15 % (issue 17: "where the forms coincide"). Sampled at
// 50 Hz to keep the tests small.
void expectNamedWithParameters(const std::string& effect, const std::vector<std::string>& names) {
  for (uint64_t seed = 20001; seed <= 20003; ++seed) {
    TrialSpec spec = drawTrialSpec(seed, {effect}, TrialForms::kOther);
    spec.sample_rate_hz = 50;
    const IdentifyResult r = identifyTension(generateTrialTest(spec));
    ASSERT_EQ(r.effects, std::vector<std::string>{effect}) << "seed " << seed;
    std::vector<double> truth = {spec.set_ratio, spec.set_yield_strain};
    if (effect == "stress_relaxation") truth = {spec.relax_g1, spec.relax_tau1_s, spec.relax_g2, spec.relax_tau2_s};
    std::vector<double> fitted;
    for (const std::string& n : names) fitted.push_back(param(r.extended, n));
    if (effect == "stress_relaxation" && fitted[1] > fitted[3])  // branches in the order of their times
      std::swap(fitted[0], fitted[2]), std::swap(fitted[1], fitted[3]);
    for (size_t i = 0; i < names.size(); ++i)
      EXPECT_NEAR(fitted[i], truth[i], 0.15 * truth[i]) << names[i] << ", seed " << seed;
  }
}

TEST(Identify, NamesASetWithAYieldStrainAndRecoversIt) {
  expectNamedWithParameters("permanent_set", {"set_ratio", "set_yield_strain"});
}

TEST(Identify, NamesRelaxationWithTwoTimesAndRecoversBoth) {
  expectNamedWithParameters("stress_relaxation", {"relax_g1", "relax_tau1_s", "relax_g2", "relax_tau2_s"});
}

}  // namespace
}  // namespace colosim

namespace colosim {
namespace {

// Relaxation's signature is the force decaying while the strain is held. A set in a form no
// law of colosim has (trial bench, harder forms) leaves the holds flat, and relaxation, which
// mimics a set through the slack bench, is then not named; relaxation in its harder forms
// (a continuous spectrum, many branches) makes the holds decay and is named. Seeds apart
// from the trials' (1-100) and their calibration's (10001+); 50 Hz to keep the test small.
TEST(Identify, NamesRelaxationOnlyWhereTheForceDecaysAtHeldStrain) {
  auto relaxes = [](const std::vector<std::string>& e) {
    return std::find(e.begin(), e.end(), "stress_relaxation") != e.end();
  };
  for (uint64_t seed = 20001; seed <= 20004; ++seed) {
    for (const char* effect : {"permanent_set", "stress_relaxation"}) {
      TrialSpec spec = drawTrialSpec(seed, {effect}, TrialForms::kHarder);
      spec.sample_rate_hz = 50;
      const IdentifyResult r = identifyTension(generateTrialTest(spec));
      ASSERT_GE(r.hold_decay.holds, 4) << effect << ", seed " << seed;
      if (std::string(effect) == "permanent_set") {
        EXPECT_LT(std::abs(r.hold_decay.z()), 5.0) << "seed " << seed;
        EXPECT_FALSE(relaxes(r.effects)) << "seed " << seed;
      } else {
        EXPECT_GT(r.hold_decay.z(), 10.0) << "seed " << seed;
        EXPECT_GT(r.hold_decay.relative, 0.005) << "seed " << seed;
        EXPECT_EQ(r.effects, std::vector<std::string>{effect}) << "seed " << seed;
      }
    }
  }
}

// Force that rises while the strain is held is softening that heals at rest, a form the
// softening law has not (trial bench, harder forms). Beside a stiffening curve that is not
// Fung's, its misfit is the size of the curve's own, and the pair paid by 1.25 in 4 of 30
// calibration cases; with the signature it needs the single effect's 1.05 (seeds 1-100:
// 68 of 100 pairs named). Seeds apart from the trials' and their calibration's; 50 Hz.
// The pair is not always named (the healed softening can be too small to pay even 1.05),
// so the test asks for most of twelve seeds.
TEST(Identify, NamesSofteningBesideStiffeningWhereTheForceRecoversAtRest) {
  int named = 0;
  for (uint64_t seed = 20001; seed <= 20012; ++seed) {
    TrialSpec spec = drawTrialSpec(seed, {"strain_stiffening", "cyclic_softening"}, TrialForms::kHarder);
    spec.sample_rate_hz = 50;
    const IdentifyResult r = identifyTension(generateTrialTest(spec));
    EXPECT_LT(r.hold_decay.z(), -10.0) << "seed " << seed;
    EXPECT_LT(r.hold_decay.relative, -0.003) << "seed " << seed;
    std::vector<std::string> e = r.effects;
    std::sort(e.begin(), e.end());
    named += e == std::vector<std::string>{"cyclic_softening", "strain_stiffening"};
  }
  EXPECT_GE(named, 8);  // when written: 9 of 12, and 5 of 12 without the signature
}

}  // namespace
}  // namespace colosim

namespace colosim {
namespace {

// A set that every cycle past the yield strain adds to, shaking down (each cycle adds less
// than the last: a form no law of colosim has, trial bench, harder forms), was named
// softening + set in 9 of 20 calibration cases by a set that grows with the largest strain
// only: softening driven by the accumulated strain took the growth. With the set's ratchet
// (kept when it pays as a second effect would) it is mostly named alone, and the law ratchets.
// Seeds apart from the trials' and their calibration's, where the bench drew the shakedown
// ratchet; 50 Hz.
TEST(Identify, NamesASetThatGrowsWithEveryCycleAloneAndItsLawRatchets) {
  int cases = 0, named = 0, ratchets = 0;
  for (uint64_t seed = 20001; cases < 8; ++seed) {
    TrialSpec spec = drawTrialSpec(seed, {"permanent_set"}, TrialForms::kHarder);
    if (spec.set_form != "shakedown_ratchet") continue;
    ++cases;
    spec.sample_rate_hz = 50;
    const IdentifyResult r = identifyTension(generateTrialTest(spec));
    named += r.effects == std::vector<std::string>{"permanent_set"};
    ratchets += r.extended.law.set_ratcheting && r.extended.law.set_ratchet > 0;
  }
  // When written: named alone 6 of 8 (twice with softening beside it), the law ratchets in
  // all 8. Calibration seeds (drawn sampling rates): named alone 10 of 11, against 2 of 11
  // with the plain set. Since softening beside a set must improve the toe of the
  // reloadings (session 36): 8 of 8.
  EXPECT_GE(named, 7);
  EXPECT_GE(ratchets, 7);
}

}  // namespace
}  // namespace colosim

namespace colosim {
namespace {

// Softening's signatures on reloading (docs/identification.md, "On reloading"): the
// reloadings are softer than the virgin loading at a given force, and the toe of the
// reloadings, where a set moves the strain at which force starts, is fitted better with
// softening than without. A set that recovers in slack (trial bench, harder forms), on a
// staircase, was named softening alone in 7 of 50 trials (seeds 1-100): softening's held-out
// ratio beat the set's. Softening in the forms that damage the virgin loading as it goes
// (driven by the largest strain: other forms, and one of the harder ones) must still be
// named. Seeds apart from the trials' and their calibration's; 50 Hz.
TEST(Identify, TellsASetFromSofteningOnReloading) {
  struct Tally {
    int cases = 0, softening_named = 0, softening_alone_or_with_set = 0, hidden_named = 0, decided_by_signature = 0;
  };
  auto has = [](const std::vector<std::string>& e, const char* name) {
    return std::find(e.begin(), e.end(), name) != e.end();
  };
  auto run = [&](const char* effect, const char* form, TrialForms forms, bool staircases, int n) {
    Tally t;
    for (uint64_t seed = 20001; t.cases < n && seed < 20400; ++seed) {
      TrialSpec spec = drawTrialSpec(seed, {effect}, forms);
      const std::string& drawn = std::string(effect) == "permanent_set" ? spec.set_form : spec.soften_form;
      if (forms == TrialForms::kHarder && drawn != form) continue;
      if (staircases && spec.protocol != "staircase") continue;
      ++t.cases;
      spec.sample_rate_hz = 50;
      const IdentifyResult r = identifyTension(generateTrialTest(spec));
      t.softening_named += has(r.effects, "cyclic_softening");
      t.softening_alone_or_with_set += has(r.effects, "cyclic_softening") &&
                                       (r.effects.size() == 1 || has(r.effects, "permanent_set"));
      t.hidden_named += r.effects == std::vector<std::string>{effect};
      // The rule decided it where a candidate it excluded held out better than the one chosen.
      for (const CandidateEvidence& e : r.evidence) {
        if (!e.without_signature) continue;
        for (const CandidateEvidence& c : r.evidence)
          if (c.round == e.round && c.chosen && e.heldout_ratio > c.heldout_ratio) {
            ++t.decided_by_signature;
            break;
          }
      }
      std::string named;
      for (const std::string& e : r.effects) named += e + " ";
      std::printf("%s %s seed %llu: reloading slope %.3f, named %s\n", effect, form,
                  static_cast<unsigned long long>(seed), r.reload_slope_ratio, named.c_str());
    }
    return t;
  };
  const Tally set = run("permanent_set", "recovering", TrialForms::kHarder, true, 6);
  const Tally soft_acc = run("cyclic_softening", "recovering_accumulated", TrialForms::kHarder, false, 3);
  const Tally soft_max = run("cyclic_softening", "recovering_largest", TrialForms::kHarder, false, 3);
  const Tally soft_other = run("cyclic_softening", "other", TrialForms::kOther, false, 3);
  // When written: the set named alone in 5 of 6, the rule deciding one of them; the sixth
  // (seed 20012) named stiffening + softening, a pair the signature does not judge (the
  // trials' stiffening + set named stiffening + softening, docs/identification-trials.md).
  EXPECT_EQ(set.softening_alone_or_with_set, 0);
  EXPECT_GE(set.hidden_named, 5);
  EXPECT_GE(set.decided_by_signature, 1);
  EXPECT_GE(soft_acc.softening_named + soft_max.softening_named + soft_other.softening_named, 8);
  EXPECT_EQ(soft_other.decided_by_signature, 0);
}

}  // namespace
}  // namespace colosim
