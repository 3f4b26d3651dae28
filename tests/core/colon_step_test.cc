#include "core/colon_step.h"

#include <random>

#include <gtest/gtest.h>

#include "tests/core/colon_energy_check.h"
#include "fixture.h"
#include "trainer/assets.h"
#include "tests/random_vec3.h"
#include "step.h"

namespace colosim {
namespace {

ColonModel straightColon(int n, double k, double c, const Vec3& g, double ea = 28.9, double ec = 0.05) {
  Points q(3, n);
  for (int i = 0; i < n; ++i) q.col(i) = Vec3(0.015 * i, 0, 0);
  return buildColonModelFromPoints(q, Eigen::VectorXd::Constant(n, 0.02), 0.4, k, c, g,
                                   std::make_shared<VoigtLaw>(ea, ec));
}

ColonModel adult(double ea_override = 0) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  const Anatomy a = loadAnatomy(test::asset("anatomy/adult.json"));
  if (ea_override > 0) p.colon.tension_EA_N = ea_override;
  return buildColonModel(a, p.colon);
}

TEST(ColonStep, StraightColonWithoutExternalForceStaysAtRest) {
  const ColonModel m = straightColon(30, 1000, 20, Vec3::Zero());
  ColonState s = makeColonState(m);
  for (int k = 0; k < 2000; ++k) stepColon(m, s, kDt);
  EXPECT_EQ(s.v.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((s.q - m.q_rest).cwiseAbs().maxCoeff(), 0.0);
}

TEST(ColonStep, StretchedElementPullsWithEATimesStrain) {
  const double ea = 28.9;
  const ColonModel m = straightColon(2, 0, 0, Vec3::Zero(), ea, 0.0);
  ColonState s = makeColonState(m);
  const double strain = 0.1;
  s.q.col(1) = Vec3(0.015 * (1 + strain), 0, 0);
  stepColon(m, s, 1e-9);  // a negligible step: the forces are those of the stretched state
  EXPECT_NEAR(s.tension_force_N(0), ea * strain, 1e-12);
  EXPECT_NEAR(s.force(3), -ea * strain, 1e-12);  // pulls q_1 back towards q_0
  EXPECT_NEAR(s.force(0), ea * strain, 1e-12);
}

TEST(ColonStep, EndLoadsStretchEveryElementToLoadOverEA) {
  // A free chain (no mesentery) pulled apart by equal and opposite end loads P settles
  // with every element at strain P / EA (with geometric update: exact for a straight chain).
  const double ea = 28.9, load = 2.0;
  const ColonModel m = straightColon(12, 0, 0, Vec3::Zero(), ea, 0.5);
  ColonState s = makeColonState(m);
  test::stepUnderEndLoads(m, s, load, 20000, kDt);
  for (int e = 0; e + 1 < m.n; ++e) {
    double strain, rate;
    elementStrain(m, s, e, &strain, &rate);
    EXPECT_NEAR(strain, load / ea, 1e-6 * load / ea) << e;
  }
}

TEST(ColonStep, StaticSagUnderGravityIsRhoGOverK) {
  // A horizontal colon held by a uniform mesentery k sags uniformly by rho g / k: the
  // tension elements do not stretch under a uniform translation.
  const double k = 800, rho = 0.4, g = 9.81;
  const ColonModel m = straightColon(25, k, 40, Vec3(0, 0, -g));
  ColonState s = makeColonState(m);
  for (int i = 0; i < 5000; ++i) stepColon(m, s, kDt);
  for (int i = 0; i < m.n; ++i) {
    EXPECT_NEAR(s.q(2, i) - m.q_rest(2, i), -rho * g / k, 1e-9) << i;
    EXPECT_NEAR(s.q(0, i), m.q_rest(0, i), 1e-12);
  }
}

TEST(ColonStep, EnergyNeverIncreasesWithDamping) {
  // A random kick on top of the fall under gravity.
  test::expectEnergyNeverIncreases(adult(), 3000, kDt);
}

TEST(ColonStep, SixtySecondsOfSettlingStayBoundedAndFinite) {
  const ColonModel m = adult();
  ColonState s = makeColonState(m);
  double max_disp = 0;
  for (int k = 0; k < 60000; ++k) {
    stepColon(m, s, kDt);
    ASSERT_TRUE(s.solver_ok);
    if (k % 1000 == 999) {
      ASSERT_TRUE(s.q.allFinite() && s.v.allFinite()) << "t = " << s.time_s;
      max_disp = std::max(max_disp, (s.q - m.q_rest).colwise().norm().maxCoeff());
    }
  }
  EXPECT_LT(max_disp, 0.15);                       // the sigmoid hangs a few cm, no more
  EXPECT_LT(s.v.colwise().norm().maxCoeff(), 1e-6); // and has come to rest
}

TEST(ColonStep, StableWithAWholeTubeAxialRigidity) {
  // EA ~ 700 N (a whole-tube wall modulus): explicit Euler would diverge at 1 ms.
  const ColonModel m = adult(700.0);
  ColonState s = makeColonState(m);
  std::mt19937 rng(12);
  std::normal_distribution<double> n01(0.0, 0.5);
  for (int i = 0; i < m.n; ++i) s.v.col(i) = test::randomVec3(n01, rng);
  const double e0 = colonEnergy(m, s).total();
  for (int k = 0; k < 5000; ++k) stepColon(m, s, kDt);
  ASSERT_TRUE(s.q.allFinite());
  EXPECT_LT(colonEnergy(m, s).total(), e0);
}

TEST(ColonStep, SameInputsGiveBitIdenticalStates) {
  const ColonModel m = adult();
  auto run = [&] {
    ColonState s = makeColonState(m);
    s.v.col(40) = Vec3(0.3, -0.2, 0.1);
    test::stepUnderASwingingLoad(m, s, 3000, kDt);
    return s;
  };
  const ColonState a = run(), b = run();
  EXPECT_EQ(hashColonState(a), hashColonState(b));
  EXPECT_EQ(getColonState(a), getColonState(b));
}

TEST(ColonStep, SnapshotRestoresTheExactState) {
  const ColonModel m = adult();
  ColonState a = makeColonState(m);
  for (int k = 0; k < 500; ++k) stepColon(m, a, kDt);
  const std::vector<double> snap = getColonState(a);
  ColonState b = makeColonState(m);
  setColonState(snap, b);
  for (int k = 0; k < 500; ++k) {
    stepColon(m, a, kDt);
    stepColon(m, b, kDt);
  }
  EXPECT_EQ(hashColonState(a), hashColonState(b));
  EXPECT_THROW(setColonState(std::vector<double>(3, 0.0), b), std::invalid_argument);
}

TEST(ColonStep, InternalForcesBalanceAndGravityCarriesTheWholeMass) {
  const ColonModel m = adult();
  ColonState s = makeColonState(m);
  for (int k = 0; k < 300; ++k) stepColon(m, s, kDt);
  // Sum of the gravity load equals the total mass times g.
  const double total_mass = m.mass_rowsum_kg.sum();
  EXPECT_NEAR(total_mass, 0.4 * m.length_m(), 1e-12);
  // Tension forces alone sum to zero: switch gravity and mesentery off.
  ColonModel free = m;
  free.gravity_m_per_s2.setZero();
  free.mesentery_K.setZero();
  free.mesentery_C.setZero();
  ColonState t = s;
  t.constant_system_dt_s = -1;
  stepColon(free, t, 1e-9);
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < m.n; ++i) sum += t.force.segment<3>(3 * i);
  EXPECT_LT(sum.norm(), 1e-12);
}

// Limits (docs/hardening.md): a NaN load stops the colon for the step (solver_ok false,
// v = 0, q unchanged, time advances); a control point kicked faster than
// max_speed_m_per_s is slowed to it and counted.
TEST(ColonStep, NonFiniteSolveStopsTheColonAndFastPointsAreSlowed) {
  const ColonModel m = adult();
  ColonState s = makeColonState(m);
  for (int k = 0; k < 20; ++k) stepColon(m, s, 1e-3);
  const Points q = s.q;
  SplineLoad bad;
  bad.segment = 10;
  bad.p = 0.5;
  bad.force_N = Vec3(0, std::nan(""), 0);
  s.loads.push_back(bad);
  const double t0 = s.time_s;
  stepColon(m, s, 1e-3);
  s.loads.clear();
  EXPECT_FALSE(s.solver_ok);
  EXPECT_EQ(s.v.norm(), 0.0);
  EXPECT_TRUE(s.q == q);
  EXPECT_DOUBLE_EQ(s.time_s, t0 + 1e-3);
  stepColon(m, s, 1e-3);
  EXPECT_TRUE(s.solver_ok);
  EXPECT_EQ(s.limited_points, 0);

  s.v.col(40) = Vec3(3 * m.max_speed_m_per_s, 0, 0);
  stepColon(m, s, 1e-3);
  EXPECT_GE(s.limited_points, 1);
  EXPECT_GT(s.asked_speed_m_per_s, m.max_speed_m_per_s);
  for (int i = 0; i < m.n; ++i) EXPECT_LE(s.v.col(i).norm(), m.max_speed_m_per_s * (1 + 1e-12));
}

}  // namespace
}  // namespace colosim
