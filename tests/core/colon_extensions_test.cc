// colon_bending and mesentery_stiffening (core/colon_extensions.h): analytic checks of the
// laws, their use in the implicit step, energy, stability at 1 ms, and default-off identity.
#include "core/colon_extensions.h"

#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "core/colon_step.h"
#include "tests/core/colon_energy_check.h"
#include "fixture.h"
#include "trainer/assets.h"
#include "tests/random_vec3.h"
#include "step.h"

namespace colosim {
namespace {

ColonModel chain(const Points& q, double k, double c, const Vec3& g, double ea = 28.9, double ec = 0.05) {
  return buildColonModelFromPoints(q, Eigen::VectorXd::Constant(q.cols(), 0.02), 0.4, k, c, g,
                                   std::make_shared<VoigtLaw>(ea, ec));
}

Points straight(int n, double spacing_m = 0.015) {
  Points q(3, n);
  for (int i = 0; i < n; ++i) q.col(i) = Vec3(spacing_m * i, 0, 0);
  return q;
}

// Three points, elements of length l, turning by theta in the x-y plane.
Points bent3(double l, double theta) {
  Points q(3, 3);
  q.col(0) = Vec3(-l, 0, 0);
  q.col(1) = Vec3(0, 0, 0);
  q.col(2) = l * Vec3(std::cos(theta), std::sin(theta), 0);
  return q;
}

TEST(ColonBending, RestoringMomentIsEITimesTheChangeOfCurvature) {
  // A 3-point colon straight at rest, bent by theta: the force on the end point, times its
  // lever arm, is the moment EI kappa with kappa = theta / L (L = l); the same for a colon
  // curved at rest (theta0) bent further: EI (kappa - kappa0).
  const double EI = 0.02, l = 0.015;
  for (double theta0 : {0.0, 0.4}) {
    for (double dtheta : {0.01, 0.1, 0.5, 1.0}) {
      const double theta = theta0 + dtheta;
      const BendingResponse r = bendingAtPoint(Vec3(-l, 0, 0), Vec3::Zero(), l * Vec3(std::cos(theta), std::sin(theta), 0),
                                               theta0, EI, l);
      EXPECT_NEAR(r.theta_rad, theta, 1e-12);
      const Vec3 tb(std::cos(theta), std::sin(theta), 0);
      const Vec3 f2 = r.force_N[2];
      EXPECT_NEAR(f2.dot(tb), 0.0, 1e-12);  // perpendicular to the element: a pure moment
      const double moment = l * tb.cross(f2).z();  // about q_1, positive counter-clockwise
      EXPECT_NEAR(moment, -EI * (theta - theta0) / l, 1e-9 * EI / l) << theta0 << " " << dtheta;
      EXPECT_NEAR(r.energy_J, 0.5 * EI / l * dtheta * dtheta, 1e-15);
      // Internal: forces and moments balance.
      EXPECT_LT((r.force_N[0] + r.force_N[1] + r.force_N[2]).norm(), 1e-12);
      const Vec3 m = Vec3(-l, 0, 0).cross(r.force_N[0]) + (l * tb).cross(r.force_N[2]);
      EXPECT_LT(m.norm(), 1e-12);
    }
  }
}

TEST(ColonBending, ForceIsMinusTheEnergyGradientAndTheTangentIsPositiveSemidefinite) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  const double EI = 0.05, L = 0.015;
  for (int trial = 0; trial < 50; ++trial) {
    std::array<Vec3, 3> q = {Vec3(-0.015, 0, 0), Vec3::Zero(), Vec3(0.015, 0, 0)};
    for (auto& p : q) p += test::randomVec3(u, rng);
    const double theta0 = 0.5 * (trial % 3);
    const BendingResponse r = bendingAtPoint(q[0], q[1], q[2], theta0, EI, L);
    const double h = 1e-7;
    Eigen::Matrix<double, 9, 9> K;
    for (int j = 0; j < 3; ++j)
      for (int c = 0; c < 3; ++c) {
        auto qp = q, qm = q;
        qp[j](c) += h;
        qm[j](c) -= h;
        const double ep = bendingAtPoint(qp[0], qp[1], qp[2], theta0, EI, L).energy_J;
        const double em = bendingAtPoint(qm[0], qm[1], qm[2], theta0, EI, L).energy_J;
        EXPECT_NEAR(r.force_N[j](c), -(ep - em) / (2 * h), 1e-6 * (1 + r.force_N[j].norm())) << trial;
      }
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) K.block<3, 3>(3 * j, 3 * k) = r.stiffness_N_per_m[j][k];
    EXPECT_LT((K - K.transpose()).norm(), 1e-9 * K.norm());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> es(K);
    EXPECT_GE(es.eigenvalues().minCoeff(), -1e-9 * es.eigenvalues().maxCoeff()) << trial;
  }
}

TEST(ColonBending, AtTheRestAngleTheTangentIsTheExactStiffness) {
  // Gauss-Newton drops only terms proportional to theta - theta0: at rest it is exact.
  const double EI = 0.05, L = 0.015;
  const Points q = bent3(L, 0.6);
  const BendingResponse r = bendingAtPoint(q.col(0), q.col(1), q.col(2), 0.6, EI, L);
  const double h = 1e-7;
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) {
      Points qp = q, qm = q;
      qp(c, k) += h;
      qm(c, k) -= h;
      const BendingResponse a = bendingAtPoint(qp.col(0), qp.col(1), qp.col(2), 0.6, EI, L);
      const BendingResponse b = bendingAtPoint(qm.col(0), qm.col(1), qm.col(2), 0.6, EI, L);
      for (int j = 0; j < 3; ++j) {
        const Vec3 fd = -(a.force_N[j] - b.force_N[j]) / (2 * h);
        EXPECT_LT((fd - r.stiffness_N_per_m[j][k].col(c)).norm(), 1e-5 * EI / (L * L * L)) << j << k << c;
      }
    }
}

TEST(ColonBending, ABentChainStraightensInTheStepAndAStraightOneStaysStraight) {
  // No mesentery, no gravity: a chain straight at rest, bent into an arc, relaxes towards
  // straight; a straight chain with bending on stays exactly where it is.
  ColonModel m = chain(straight(9), 0, 0, Vec3::Zero(), 28.9, 0.05);
  m.bending_EI_Nm2 = 0.01;
  ColonState rest = makeColonState(m);
  for (int k = 0; k < 500; ++k) stepColon(m, rest, kDt);
  EXPECT_EQ((rest.q - m.q_rest).cwiseAbs().maxCoeff(), 0.0);

  ColonState s = makeColonState(m);
  for (int i = 0; i < m.n; ++i) s.q(1, i) = 0.5 * std::pow(s.q(0, i) - 0.06, 2);  // an arc, curvature 1 /m
  const double e0 = colonEnergy(m, s).bending_J;
  for (int k = 0; k < 3000; ++k) stepColon(m, s, kDt);
  EXPECT_LT(colonEnergy(m, s).bending_J, 0.05 * e0);
}

TEST(MesenteryStiffening, ALifterStretchedByDPullsBackWithK0TimesOnePlusBetaDSquared) {
  const double k0 = 1000, beta = 2500;  // twice as stiff at d0 = 2 cm
  for (double d : {0.0, 0.005, 0.02, 0.05}) {
    const Vec3 u = d * Vec3(0.6, 0, 0.8);
    EXPECT_NEAR((lifterForceDensity(u, k0, beta) + k0 * (1 + beta * d * d) * u).norm(), 0.0, 1e-12);
    EXPECT_NEAR((lifterForceDensity(u, k0, 0) + k0 * u).norm(), 0.0, 1e-12);
  }
  // The tangent is the derivative of the force (consistent), checked by differences.
  const Vec3 u(0.01, -0.02, 0.015);
  const Mat3 T = lifterStiffeningTangent(u, k0, beta);
  for (int c = 0; c < 3; ++c) {
    Vec3 up = u, um = u;
    up(c) += 1e-7;
    um(c) -= 1e-7;
    const Vec3 fd = -(lifterStiffeningForceDensity(up, k0, beta) - lifterStiffeningForceDensity(um, k0, beta)) / 2e-7;
    EXPECT_LT((fd - T.col(c)).norm(), 1e-6 * T.norm());
  }
  // In the step: a straight colon displaced uniformly by u (no stretch, no bend) feels the
  // lifters of its whole length: -k0 (1 + beta d^2) u L.
  ColonModel m = chain(straight(11), k0, 0, Vec3::Zero());
  m.mesentery_stiffening_per_m2 = beta;
  ColonState s = makeColonState(m);
  const Vec3 shift(0, 0.03, -0.01);
  for (int i = 0; i < m.n; ++i) s.q.col(i) += shift;
  stepColon(m, s, 1e-9);
  Vec3 total = Vec3::Zero();
  for (int i = 0; i < m.n; ++i) total += s.force.segment<3>(3 * i);
  const Vec3 want = -k0 * (1 + beta * shift.squaredNorm()) * shift * m.length_m();
  EXPECT_LT((total - want).norm(), 1e-9 * want.norm());
}

TEST(MesenteryStiffening, StaticSagSolvesTheCubicRhoGEqualsK0OnePlusBetaDSquaredD) {
  const double k0 = 60, beta = 2500, rho = 0.4, g = 9.81;  // free lifters: linear sag 6.5 cm
  ColonModel m = chain(straight(21), k0, 8, Vec3(0, 0, -g));
  m.mesentery_stiffening_per_m2 = beta;
  ColonState s = makeColonState(m);
  for (int k = 0; k < 8000; ++k) stepColon(m, s, kDt);
  // Newton on k0 (1 + beta d^2) d = rho g.
  double d = rho * g / k0;
  for (int it = 0; it < 50; ++it) d -= (k0 * (1 + beta * d * d) * d - rho * g) / (k0 * (1 + 3 * beta * d * d));
  EXPECT_LT(d, 0.5 * rho * g / k0);  // the stiffening matters here
  for (int i = 0; i < m.n; ++i) EXPECT_NEAR(m.q_rest(2, i) - s.q(2, i), d, 1e-7) << i;
}

TEST(ColonCompression, AShortenedElementPushesWithCEATimesStrainAndAStretchedOnePullsWithEA) {
  const double ea = 28.9, c = 0.1;
  ColonModel m = chain(straight(2), 0, 0, Vec3::Zero(), ea, 0.0);
  m.compression_stiffness_fraction = c;
  for (double strain : {-0.2, -0.05, 0.05, 0.2}) {
    ColonState s = makeColonState(m);
    s.q.col(1) = Vec3(0.015 * (1 + strain), 0, 0);
    stepColon(m, s, 1e-9);  // a negligible step: the forces of the deformed state
    const double expected = (strain < 0 ? c : 1.0) * ea * strain;
    EXPECT_NEAR(s.tension_force_N(0), expected, 1e-12) << strain;
    EXPECT_NEAR(s.force(3), -expected, 1e-12) << strain;
    // Energy: the integral of the force over the element's length change.
    const double energy_J = 0.5 * expected * strain * 0.015;
    EXPECT_NEAR(colonEnergy(m, s).tension_J, energy_J, 1e-9 * energy_J) << strain;
  }
}

TEST(ColonCompression, EndLoadsShorteningAStraightChainGiveEveryElementMinusPOverCEA) {
  // A free straight chain pushed together by equal and opposite end loads P settles with
  // every element at strain -P / (c EA) (it stays straight: no load across it).
  const double ea = 28.9, c = 0.2, load = 0.5;
  ColonModel m = chain(straight(12), 0, 0, Vec3::Zero(), ea, 0.5);
  m.compression_stiffness_fraction = c;
  ColonState s = makeColonState(m);
  test::stepUnderEndLoads(m, s, -load, 20000, kDt);
  for (int e = 0; e + 1 < m.n; ++e) {
    double strain, rate;
    elementStrain(m, s, e, &strain, &rate);
    EXPECT_NEAR(strain, -load / (c * ea), 1e-6 * load / (c * ea)) << e;
  }
}

// The adult colon of the tuned patient's parameters, with `change` applied to them.
template <class Change>
ColonModel adultColonWith(Change change) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  change(p.colon);
  return buildColonModel(loadAnatomy(test::asset("anatomy/adult.json")), p.colon);
}

// The tuned patient's colon with `field` set to each of `bad` is refused by the model's build.
void expectOutOfRangeRefused(double ColonParams::*field, std::initializer_list<double> bad) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  const Anatomy a = loadAnatomy(test::asset("anatomy/adult.json"));
  for (double value : bad) {
    p.colon.*field = value;
    EXPECT_THROW(buildColonModel(a, p.colon), std::invalid_argument) << value;
  }
}

TEST(ColonCompression, EnergyNeverIncreasesWithDampingAndSoftCompression) {
  const ColonModel m = adultColonWith([](ColonParams& c) { c.compression_stiffness_fraction = 0.05; });
  test::expectEnergyNeverIncreases(m, 3000, kDt, 11, 0.5);
}

TEST(ColonCompression, DefaultIsThePaperElementASofterOneMovesOtherwiseAndOutOfRangeIsRefused) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  EXPECT_EQ(p.colon.compression_stiffness_fraction, 1.0);  // the key is optional: absent, the paper's element
  const Anatomy a = loadAnatomy(test::asset("anatomy/adult.json"));
  const ColonModel m = buildColonModel(a, p.colon);
  ColonModel soft = m;
  soft.compression_stiffness_fraction = 0.3;
  ColonState s = makeColonState(m), t = makeColonState(soft);
  std::mt19937 rng(5);
  std::normal_distribution<double> n01(0.0, 0.3);
  for (int i = 0; i < m.n; ++i) {
    const double x = n01(rng), y = n01(rng), z = n01(rng);
    s.v.col(i) = t.v.col(i) = Vec3(x, y, z);
  }
  for (int k = 0; k < 200; ++k) {
    stepColon(m, s, kDt);
    stepColon(soft, t, kDt);
  }
  EXPECT_GT((s.q - t.q).cwiseAbs().maxCoeff(), 1e-6);
  expectOutOfRangeRefused(&ColonParams::compression_stiffness_fraction, {0.0, -0.1, 1.5, std::nan("")});
}

// Lifters along the colon (ColonModel::mesentery_axial_ratio a): a straight colon shifted
// bodily along its axis by d feels -a k0 d L, shifted across it -k0 d L (no stretch, no
// bend: only the lifters act), and the energy is the matching quadratic.
TEST(MesenteryAxialRatio, AStraightColonSlidingAlongItselfFeelsAK0AndMovedAcrossK0) {
  const double k0 = 1000, a = 0.1;
  ColonModel m = chain(straight(11), k0, 0, Vec3::Zero());
  m.mesentery_axial_ratio = a;
  const double L = m.length_m();
  for (const Vec3& shift : {Vec3(0.02, 0, 0), Vec3(0, 0.02, -0.01), Vec3(0.01, 0.01, 0)}) {
    ColonState s = makeColonState(m);
    for (int i = 0; i < m.n; ++i) s.q.col(i) += shift;
    stepColon(m, s, 1e-9);  // a negligible step: the forces of the shifted state
    Vec3 total = Vec3::Zero();
    for (int i = 0; i < m.n; ++i) total += s.force.segment<3>(3 * i);
    const Vec3 along(shift.x(), 0, 0), across(0, shift.y(), shift.z());
    const Vec3 want = -k0 * L * (a * along + across);
    EXPECT_LT((total - want).norm(), 1e-9 * want.norm()) << shift.transpose();
    const double energy_J = 0.5 * k0 * L * (a * along.squaredNorm() + across.squaredNorm());
    EXPECT_NEAR(colonEnergy(m, s).mesentery_J, energy_J, 1e-9 * energy_J) << shift.transpose();
  }
}

TEST(MesenteryAxialRatio, EnergyNeverIncreasesWithDampingEvenWithNoAxialLifter) {
  const ColonModel m = adultColonWith([](ColonParams& c) { c.mesentery_axial_ratio = 0.0; });
  test::expectEnergyNeverIncreases(m, 3000, kDt, 11, 0.5);
}

TEST(MesenteryAxialRatio, DefaultIsThePapersIsotropicLifterAndOutOfRangeIsRefused) {
  // The key is optional: absent, the paper's lifters.
  EXPECT_EQ(loadParameters(test::asset("params/default.json")).colon.mesentery_axial_ratio, 1.0);
  expectOutOfRangeRefused(&ColonParams::mesentery_axial_ratio, {-0.1, 1.5, std::nan("")});
}

ColonModel adultWithBending(double EI, double beta) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  p.colon.bending_EI_Nm2 = EI;
  p.colon.mesentery_stiffening_per_m2 = beta;
  return buildColonModel(loadAnatomy(test::asset("anatomy/adult.json")), p.colon);
}

TEST(ColonExtensions, EnergyNeverIncreasesWithDamping) {
  test::expectEnergyNeverIncreases(adultWithBending(0.05, 2500), 3000, kDt);
}

TEST(ColonExtensions, AdultColonWithBothOnStaysBoundedAtOneMillisecond) {
  // The caecal end pulled by a load cycling between 0 and 8 N for 4 s at dt = 1 ms, with a
  // stiff bending rigidity and lifters twice as stiff at 2 cm.
  const ColonModel m = adultWithBending(0.1, 2500);
  ColonState s = makeColonState(m);
  const Vec3 out = (m.q_rest.col(m.n - 1) - m.q_rest.col(m.n - 2)).normalized();
  double max_disp = 0;
  for (int k = 0; k < 4000; ++k) {
    s.loads.clear();
    SplineLoad pull;
    pull.segment = m.n - 2;
    pull.p = 1.0;
    pull.force_N = 4.0 * (1.0 - std::cos(2.0 * M_PI * k * kDt / 2.0)) * out;
    s.loads.push_back(pull);
    stepColon(m, s, kDt);
    ASSERT_TRUE(s.solver_ok);
    ASSERT_TRUE(s.q.allFinite() && s.v.allFinite()) << "step " << k;
    for (int i = 0; i < m.n; ++i) max_disp = std::max(max_disp, (s.q.col(i) - m.q_rest.col(i)).norm());
  }
  EXPECT_GT(max_disp, 0.01);  // it moved
  EXPECT_LT(max_disp, 0.3);
  EXPECT_LT(s.v.cwiseAbs().maxCoeff(), 1.0);
}

TEST(ColonExtensions, ExtensionsChangeTheMotion) {
  // Honesty check for the identity test below: switched on, each extension changes the state.
  auto run = [](const ColonModel& m) {
    ColonState s = makeColonState(m);
    for (int k = 0; k < 300; ++k) stepColon(m, s, kDt);
    return hashColonState(s);
  };
  const uint64_t off = run(adultWithBending(0, 0));
  EXPECT_NE(run(adultWithBending(0.05, 0)), off);
  EXPECT_NE(run(adultWithBending(0, 2500)), off);
}

// The state hash of a fixed run (adult colon, default parameters, gravity, a kick and a
// moving load, 1500 steps of 1 ms) made by the colon step as it was before the extensions
// (commit 3f0a3f0, core/colon_step.cc), built with the project's Release flags. With both
// extensions off the step must reproduce it bit for bit.
constexpr uint64_t kUnextendedHash = 0x34b893e079419556ull;

TEST(ColonExtensions, DefaultOffIsBitIdenticalToTheUnextendedStep) {
  // The paper's model: the extensions off (params/default.json, the tuned patient, has the
  // colon bending on since session 9).
  const Parameters p = loadParameters(test::asset("params/paper.json"));
  ASSERT_EQ(p.colon.bending_EI_Nm2, 0.0);
  ASSERT_EQ(p.colon.mesentery_stiffening_per_m2, 0.0);
  const ColonModel m = buildColonModel(loadAnatomy(test::asset("anatomy/adult.json")), p.colon);
  ColonState s = makeColonState(m);
  s.v.col(40) = Vec3(0.3, -0.2, 0.1);
  test::stepUnderASwingingLoad(m, s, 1500, kDt);
  EXPECT_EQ(hashColonState(s), kUnextendedHash) << std::hex << hashColonState(s);
}

}  // namespace
}  // namespace colosim
