#include "core/extended_tension_law.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/colon_step.h"
#include "fixture.h"
#include "trainer/assets.h"

namespace colosim {
namespace {

ExtendedLawParams allEffects() {
  ExtendedLawParams p;
  for (const std::string& e : tensionEffectNames()) p.enable(e);
  p.ea_N = 6, p.ec_Ns = 0.05, p.fung_b = 2.5, p.relax_g1 = 0.45, p.relax_tau1_s = 12;
  p.soften_d_inf = 0.25, p.soften_a_c = 1.5, p.set_ratio = 0.1;
  return p;
}

TEST(ExtendedTensionLaw, WithEveryEffectOffItIsTheVoigtLaw) {
  ExtendedLawParams p;
  p.ea_N = 28.9, p.ec_Ns = 0.05;
  const ExtendedTensionLaw law(p);
  const VoigtLaw voigt(28.9, 0.05);
  EXPECT_EQ(law.name(), "voigt");
  EXPECT_EQ(law.internalSize(), 0);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.8);
  for (int k = 0; k < 100; ++k) {
    const double e = u(rng), r = u(rng);
    const TensionResponse a = law.evaluate(e, r, 1e-3, nullptr), b = voigt.evaluate(e, r, 1e-3, nullptr);
    EXPECT_EQ(a.force_N, b.force_N);
    EXPECT_EQ(a.dforce_dstrain_N, b.dforce_dstrain_N);
    EXPECT_EQ(a.dforce_dstrainrate_Ns, b.dforce_dstrainrate_Ns);
    EXPECT_EQ(law.storedEnergy(e, nullptr), voigt.storedEnergy(e, nullptr));
  }
}

TEST(ExtendedTensionLaw, TangentIsTheDerivativeOfTheForceOfTheStep) {
  // The implicit step relies on dF/de: it must be the derivative of what evaluate() returns
  // (with the internal variables of the step start), for every effect and their mix.
  std::vector<ExtendedLawParams> laws;
  for (const std::string& e : tensionEffectNames()) {
    ExtendedLawParams p = allEffects();
    p.strain_stiffening = e == "strain_stiffening";
    p.stress_relaxation = e == "stress_relaxation";
    p.cyclic_softening = e == "cyclic_softening";
    p.permanent_set = e == "permanent_set";
    laws.push_back(p);
  }
  laws.push_back(allEffects());
  for (const ExtendedLawParams& p : laws) {
    const ExtendedTensionLaw law(p);
    std::vector<double> z(law.internalSize());
    law.initInternal(z.data());
    const double dt = 1e-3;
    for (int k = 0; k < 3000; ++k) {
      const double e = 0.4 * std::sin(0.002 * k) * std::sin(0.002 * k) + 0.02;
      law.advance(e, 0, dt, z.data());
    }
    for (double e : {0.05, 0.2, 0.35, 0.5}) {
      const double h = 1e-7;
      const double fp = law.evaluate(e + h, 0.1, dt, z.data()).force_N;
      const double fm = law.evaluate(e - h, 0.1, dt, z.data()).force_N;
      const TensionResponse r = law.evaluate(e, 0.1, dt, z.data());
      EXPECT_NEAR(r.dforce_dstrain_N, (fp - fm) / (2 * h), 1e-5 * std::abs(r.dforce_dstrain_N) + 1e-6)
          << ExtendedTensionLaw(p).parameters().size() << " parameters, e = " << e;
      EXPECT_GT(r.dforce_dstrain_N, 0.0);
      EXPECT_DOUBLE_EQ(r.dforce_dstrainrate_Ns, p.ec_Ns);
    }
  }
}

TEST(ExtendedTensionLaw, FungCurveHasTheExponentialForm) {
  ExtendedLawParams p;
  p.enable("strain_stiffening");
  p.ea_N = 6, p.ec_Ns = 0, p.fung_b = 2.5;
  const ExtendedTensionLaw law(p);
  std::vector<double> z(law.internalSize());
  law.initInternal(z.data());
  for (double e : {0.1, 0.3, 0.6}) {
    EXPECT_NEAR(law.evaluate(e, 0, 1e-3, z.data()).force_N, 6 / 2.5 * std::expm1(2.5 * e), 1e-12);
    EXPECT_NEAR(law.storedEnergy(e, z.data()), 6 / 2.5 * (std::expm1(2.5 * e) / 2.5 - e), 1e-12);
  }
  EXPECT_NEAR(law.evaluate(-0.1, 0, 1e-3, z.data()).force_N, -0.6, 1e-12);  // linear in compression
}

TEST(ExtendedTensionLaw, RelaxationAtConstantLengthFollowsThePronySeries) {
  // A fast ramp to e, then a hold: F(t) = Fe(e) (g_inf + g1 exp(-t / tau1)).
  ExtendedLawParams p;
  p.enable("stress_relaxation");
  p.ea_N = 20, p.ec_Ns = 0, p.relax_g1 = 0.5, p.relax_tau1_s = 10;
  const ExtendedTensionLaw law(p);
  std::vector<double> z(law.internalSize());
  law.initInternal(z.data());
  const double dt = 1e-3, e = 0.3;
  for (int k = 1; k <= 10; ++k) law.advance(e * k / 10, 0, dt, z.data());  // 10 ms ramp
  const double f0 = law.evaluate(e, 0, dt, z.data()).force_N;
  for (int k = 0; k < 10000; ++k) law.advance(e, 0, dt, z.data());  // 10 s hold
  const double f10 = law.evaluate(e, 0, dt, z.data()).force_N;
  EXPECT_NEAR(f0, 20 * e * (0.5 + 0.5 * std::exp(-0.005 / 10)), 1e-3);
  EXPECT_NEAR(f10 / f0, (0.5 + 0.5 * std::exp(-1.0)) / (0.5 + 0.5 * std::exp(-0.0005)), 1e-4);
}

TEST(ExtendedTensionLaw, PreconditioningSoftensRepeatedCyclesTowardsOneMinusDInf) {
  ExtendedLawParams p;
  p.enable("cyclic_softening");
  p.ea_N = 20, p.ec_Ns = 0, p.soften_d_inf = 0.3, p.soften_a_c = 0.6;
  const ExtendedTensionLaw law(p);
  std::vector<double> z(law.internalSize());
  law.initInternal(z.data());
  std::vector<double> peaks;
  for (int c = 0; c < 15; ++c) {
    for (int k = 1; k <= 100; ++k) law.advance(0.2 * k / 100, 0, 1e-2, z.data());
    peaks.push_back(law.evaluate(0.2, 0, 1e-2, z.data()).force_N);
    for (int k = 99; k >= 0; --k) law.advance(0.2 * k / 100, 0, 1e-2, z.data());
  }
  for (size_t c = 1; c < peaks.size(); ++c) EXPECT_LT(peaks[c], peaks[c - 1]);
  // After 15 cycles a = 3 = 5 a_c: within 1 % of the equilibrium 0.7 EA e.
  EXPECT_NEAR(peaks.back(), 0.7 * 20 * 0.2, 0.01 * 4);
}

TEST(ExtendedTensionLaw, AfterALargeStretchTheSampleIsSlackWhereItUsedToResist) {
  ExtendedLawParams p;
  p.enable("permanent_set");
  p.ea_N = 20, p.ec_Ns = 0, p.set_ratio = 0.1;
  const ExtendedTensionLaw law(p);
  std::vector<double> z(law.internalSize());
  law.initInternal(z.data());
  EXPECT_GT(law.evaluate(0.03, 0, 1e-3, z.data()).force_N, 0.0);  // virgin: resists at 3 %
  for (int k = 1; k <= 100; ++k) law.advance(0.5 * k / 100, 0, 1e-3, z.data());
  for (int k = 99; k >= 30; --k) law.advance(0.5 * k / 100, 0, 1e-3, z.data());
  EXPECT_NEAR(law.evaluate(0.3, 0, 1e-3, z.data()).force_N, 20 * (0.3 - 0.05), 1e-9);
  EXPECT_LT(law.evaluate(0.03, 0, 1e-3, z.data()).force_N, 0.0);  // longer now: no tension at 3 %
}

TEST(ExtendedTensionLaw, ASetWithAYieldStrainStartsOnlyBeyondIt) {
  // e_p = r max(0, e_max - e_y): stretched to 0.15 < e_y = 0.2 the sample keeps its length;
  // stretched to 0.5 it is longer by r (0.5 - 0.2) = 0.03.
  ExtendedLawParams p;
  p.enable("permanent_set");
  p.ea_N = 20, p.ec_Ns = 0, p.set_ratio = 0.1;
  ASSERT_TRUE(p.set("set_yield_strain", 0.2));
  const ExtendedTensionLaw law(p);
  ASSERT_EQ(law.parameters().back().name, "set_yield_strain");
  std::vector<double> z(law.internalSize());
  law.initInternal(z.data());
  for (int k = 1; k <= 100; ++k) law.advance(0.15 * k / 100, 0, 1e-3, z.data());
  for (int k = 99; k >= 10; --k) law.advance(0.15 * k / 100, 0, 1e-3, z.data());
  EXPECT_NEAR(law.evaluate(0.015, 0, 1e-3, z.data()).force_N, 20 * 0.015, 1e-9);
  for (int k = 10; k <= 500; ++k) law.advance(0.5 * k / 500, 0, 1e-3, z.data());
  for (int k = 499; k >= 200; --k) law.advance(0.5 * k / 500, 0, 1e-3, z.data());
  EXPECT_NEAR(law.evaluate(0.2, 0, 1e-3, z.data()).force_N, 20 * (0.2 - 0.03), 1e-9);
  EXPECT_NEAR(law.storedEnergy(0.2, z.data()), 0.5 * 20 * 0.17 * 0.17, 1e-9);
  // A yield strain of 0 is the law without a threshold.
  ExtendedLawParams q = p;
  q.set_yield_strain = 0;
  ExtendedLawParams r = p;
  r.set_yield = false;
  EXPECT_EQ(ExtendedTensionLaw(r).parameters().size() + 1, law.parameters().size());
  std::vector<double> zq(law.internalSize()), zr(law.internalSize());
  ExtendedTensionLaw(q).initInternal(zq.data());
  ExtendedTensionLaw(r).initInternal(zr.data());
  for (int k = 1; k <= 300; ++k) {
    const double e = 0.4 * std::sin(0.02 * k) * std::sin(0.02 * k);
    ExtendedTensionLaw(q).advance(e, 0, 1e-3, zq.data());
    ExtendedTensionLaw(r).advance(e, 0, 1e-3, zr.data());
    EXPECT_EQ(ExtendedTensionLaw(q).evaluate(e, 0, 1e-3, zq.data()).force_N,
              ExtendedTensionLaw(r).evaluate(e, 0, 1e-3, zr.data()).force_N);
  }
  p.set_yield_strain = -0.1;
  EXPECT_THROW(ExtendedTensionLaw{p}, std::invalid_argument);
}

TEST(ExtendedTensionLaw, ARatchetingSetGrowsWithEveryCyclePastTheYieldStrain) {
  // e_p = r max(0, e_max - e_y) + c a_y: cycles between 0 and 0.4 with e_y = 0.1 add
  // c (0.4 - 0.1) each, not only the first; the largest strain alone gives r (0.4 - 0.1).
  ExtendedLawParams p;
  p.enable("permanent_set");
  p.ea_N = 20, p.ec_Ns = 0, p.set_ratio = 0.1;
  ASSERT_TRUE(p.set("set_yield_strain", 0.1));
  ASSERT_TRUE(p.set("set_ratchet", 0.05));
  const ExtendedTensionLaw law(p);
  ASSERT_EQ(law.parameters().back().name, "set_ratchet");
  std::vector<double> z(law.internalSize());
  law.initInternal(z.data());
  for (int cycle = 1; cycle <= 4; ++cycle) {
    for (int k = 1; k <= 400; ++k) law.advance(0.4 * k / 400, 0, 1e-3, z.data());
    for (int k = 399; k >= 0; --k) law.advance(0.4 * k / 400, 0, 1e-3, z.data());
    const double set = 0.1 * 0.3 + 0.05 * 0.3 * cycle;
    EXPECT_NEAR(law.evaluate(0.3, 0, 1e-3, z.data()).force_N, 20 * (0.3 - set), 1e-9) << "cycle " << cycle;
    EXPECT_NEAR(law.evaluate(0.5 * set, 0, 1e-3, z.data()).force_N, -20 * 0.5 * set, 1e-9)
        << "compressed below the set, cycle " << cycle;
  }
  // Cycles that stay below the yield strain add nothing.
  std::vector<double> low(law.internalSize());
  law.initInternal(low.data());
  for (int cycle = 0; cycle < 3; ++cycle)
    for (int k = 0; k <= 200; ++k) law.advance(0.1 * std::sin(M_PI * k / 200), 0, 1e-3, low.data());
  EXPECT_EQ(law.evaluate(0.05, 0, 1e-3, low.data()).force_N, 20 * 0.05);
  // A ratchet of 0 is the set that grows with the largest strain only, to the bit.
  ExtendedLawParams plain = p;
  plain.set_ratcheting = false;
  ExtendedLawParams zero = p;
  zero.set_ratchet = 0;
  std::vector<double> za(law.internalSize()), zb(law.internalSize());
  const ExtendedTensionLaw a(plain), b(zero);
  a.initInternal(za.data());
  b.initInternal(zb.data());
  for (int k = 1; k <= 3000; ++k) {
    const double e = 0.5 * std::sin(0.01 * k) * std::sin(0.01 * k);
    a.advance(e, 0, 1e-3, za.data());
    b.advance(e, 0, 1e-3, zb.data());
    EXPECT_EQ(a.evaluate(e, 0, 1e-3, za.data()).force_N, b.evaluate(e, 0, 1e-3, zb.data()).force_N);
  }
  for (double bad : {-0.01, 1.0, std::nan("")}) {
    p.set_ratchet = bad;
    EXPECT_THROW(ExtendedTensionLaw{p}, std::invalid_argument) << bad;
  }
}

TEST(ExtendedTensionLaw, AStiffeningCurveWithAStraighteningStrainIsStraightBeyondIt) {
  // dFe/dx = EA exp(b x) up to x_c, EA exp(b x_c) beyond: a toe, then a linear region.
  ExtendedLawParams p;
  p.enable("strain_stiffening");
  p.ea_N = 4, p.ec_Ns = 0, p.fung_b = 5;
  ASSERT_TRUE(p.set("fung_cap_strain", 0.2));
  const ExtendedTensionLaw law(p);
  ASSERT_EQ(law.parameters().back().name, "fung_cap_strain");
  std::vector<double> z(law.internalSize());
  law.initInternal(z.data());
  const double k_c = 4 * std::exp(1.0);  // the tangent at and beyond x_c [N]
  const double f_c = 4 / 5.0 * (std::exp(1.0) - 1);  // Fe(x_c) [N]
  for (double x : {0.25, 0.4, 0.8}) {
    const TensionResponse r = law.evaluate(x, 0, 1e-3, z.data());
    EXPECT_NEAR(r.dforce_dstrain_N, k_c, 1e-9 * k_c) << x;
    EXPECT_NEAR(r.force_N, f_c + k_c * (x - 0.2), 1e-9) << x;
  }
  // Below x_c it is the Fung curve, and the force is the derivative of the energy.
  ExtendedLawParams plain = p;
  plain.fung_capped = false;
  EXPECT_EQ(law.evaluate(0.15, 0, 1e-3, z.data()).force_N, ExtendedTensionLaw(plain).evaluate(0.15, 0, 1e-3, z.data()).force_N);
  for (double x : {0.1, 0.2, 0.3, 0.6}) {
    const double h = 1e-6;
    const double dw = (law.storedEnergy(x + h, z.data()) - law.storedEnergy(x - h, z.data())) / (2 * h);
    EXPECT_NEAR(dw, law.evaluate(x, 0, 1e-3, z.data()).force_N, 1e-6) << x;
  }
  for (double bad : {0.0, -0.1, std::nan("")}) {
    p.fung_cap_strain = bad;
    EXPECT_THROW(ExtendedTensionLaw{p}, std::invalid_argument) << bad;
  }
}

TEST(ExtendedTensionLaw, RejectsParametersOutOfRange) {
  ExtendedLawParams p = allEffects();
  p.relax_g1 = 1.2;
  EXPECT_THROW(ExtendedTensionLaw{p}, std::invalid_argument);
  p = allEffects();
  p.ea_N = NAN;
  EXPECT_THROW(ExtendedTensionLaw{p}, std::invalid_argument);
  EXPECT_THROW(p.enable("viscoplasticity"), std::invalid_argument);
}

TEST(ExtendedTensionLaw, AdultColonWithEveryEffectStaysBoundedAtOneMillisecond) {
  // The implicit step with an extended law: 4 s at dt = 1 ms, every effect on, at the
  // paper's rigidity, with the caecal end pulled by a load cycling between 0 and 8 N
  // (loading, holds in tension, unloading: the history variables all move, and the Fung
  // tangent grows with the stretch).
  Parameters prm = loadParameters(test::asset("params/default.json"));
  const Anatomy a = loadAnatomy(test::asset("anatomy/adult.json"));
  ExtendedLawParams p = allEffects();
  p.ea_N = prm.colon.tension_EA_N;
  p.ec_Ns = prm.colon.tension_EC_Ns;
  p.relax_tau1_s = 0.5;
  p.soften_a_c = 0.05;
  const ColonModel m = buildColonModel(a, prm.colon, std::make_shared<ExtendedTensionLaw>(p));
  ColonState s = makeColonState(m);
  const Vec3 out = (m.q_rest.col(m.n - 1) - m.q_rest.col(m.n - 2)).normalized();
  double max_strain = 0;
  for (int k = 0; k < 4000; ++k) {
    const double t = k * 1e-3;
    s.loads.clear();
    SplineLoad pull;
    pull.segment = m.n - 2;
    pull.p = 1.0;
    pull.force_N = 4.0 * (1.0 - std::cos(2.0 * M_PI * t / 2.0)) * out;  // 0 .. 8 N, period 2 s
    s.loads.push_back(pull);
    stepColon(m, s, 1e-3);
    ASSERT_TRUE(s.solver_ok);
    ASSERT_TRUE(s.q.allFinite() && s.v.allFinite()) << "step " << k;
    for (int e = 0; e + 1 < m.n; ++e) {
      double strain, rate;
      elementStrain(m, s, e, &strain, &rate);
      max_strain = std::max(max_strain, strain);
    }
  }
  for (double z : s.tension_internal) ASSERT_TRUE(std::isfinite(z));
  double max_disp = 0;
  for (int i = 0; i < m.n; ++i) max_disp = std::max(max_disp, (s.q.col(i) - m.q_rest.col(i)).norm());
  EXPECT_GT(max_strain, 0.05);  // the effects were exercised
  EXPECT_LT(max_strain, 1.0);
  EXPECT_LT(max_disp, 0.3);
  EXPECT_LT(s.v.cwiseAbs().maxCoeff(), 1.0);
  std::printf("max element strain %.3f, max displacement %.3f m\n", max_strain, max_disp);
}

}  // namespace
}  // namespace colosim
