// Abdominal pressure (core/abdominal_pressure.h): the extra lifters' loads integrate the
// force density exactly, enter the implicit step with their stiffness, hold a pressed
// region nearer its rest shape, and the ramp.
#include "core/abdominal_pressure.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/colon_step.h"

namespace colosim {
namespace {

ColonModel pelvicChain(int n, double k, const Vec3& g) {
  Points q(3, n);
  for (int i = 0; i < n; ++i) q.col(i) = Vec3(0.015 * i, 0, 0);
  return buildColonModelFromPoints(q, Eigen::VectorXd::Constant(n, 0.02), 0.4, k, 0.2 * k, g,
                                   std::make_shared<VoigtLaw>(28.9, 0.05));
}

TEST(AbdominalPressure, LoadsIntegrateTheForceDensityOverTheRegion) {
  ColonModel m = pelvicChain(21, 60, Vec3::Zero());
  ColonState s = makeColonState(m);
  // The whole chain moved by d and moving at v: a spline of moved control points is the rest
  // spline moved (the blending weights sum to 1), so the loads sum to -(k d + c v) times the
  // pressed length, whatever the quadrature.
  const Vec3 d(0.0, 0.01, -0.02), v(0.1, 0.0, 0.05);
  for (int i = 0; i < m.n; ++i) s.q.col(i) += d, s.v.col(i) = v;
  RegionSupport r;
  r.anchor_q = m.q_rest;  // held where it was at rest
  r.first_segment = 5;
  r.last_segment = 12;  // 8 segments of 1.5 cm
  r.stiffness_N_per_m2 = 1000;
  r.damping_Ns_per_m2 = 20;
  std::vector<SplineLoad> loads;
  addRegionSupport(m, s, r, loads);
  ASSERT_EQ(loads.size(), 8u * Gauss4::kCount);
  Vec3 total = Vec3::Zero();
  double k_total = 0, c_total = 0;
  for (const SplineLoad& l : loads) {
    EXPECT_GE(l.segment, 5);
    EXPECT_LE(l.segment, 12);
    total += l.force_N;
    k_total += l.stiffness_N_per_m(0, 0);
    c_total += l.damping_Ns_per_m(1, 1);
    EXPECT_EQ(l.stiffness_N_per_m(0, 1), 0.0);
  }
  const double len = 8 * 0.015;
  EXPECT_LT((total + len * (1000 * d + 20 * v)).norm(), 1e-12);
  EXPECT_NEAR(k_total, 1000 * len, 1e-9);
  EXPECT_NEAR(c_total, 20 * len, 1e-9);
  // Nothing pressed: no loads; segments beyond the colon are clamped to it.
  loads.clear();
  r.stiffness_N_per_m2 = r.damping_Ns_per_m2 = 0;
  addRegionSupport(m, s, r, loads);
  EXPECT_TRUE(loads.empty());
  r.stiffness_N_per_m2 = 10;
  r.first_segment = -4;
  r.last_segment = 100;
  addRegionSupport(m, s, r, loads);
  EXPECT_EQ(loads.size(), static_cast<size_t>(m.n - 1) * Gauss4::kCount);
  // Anchored where the colon is now: no force, the same stiffness; without an anchor, nothing;
  // an anchor of another colon is refused.
  loads.clear();
  r.anchor_q = s.q;
  r.damping_Ns_per_m2 = 0;
  addRegionSupport(m, s, r, loads);
  for (const SplineLoad& l : loads) EXPECT_LT(l.force_N.norm(), 1e-15);
  loads.clear();
  r.anchor_q.resize(3, 0);
  addRegionSupport(m, s, r, loads);
  EXPECT_TRUE(loads.empty());
  r.anchor_q = Points::Zero(3, 5);
  EXPECT_THROW(addRegionSupport(m, s, r, loads), std::invalid_argument);
}

TEST(AbdominalPressure, PressedRegionSagsLessUnderGravity) {
  // A straight chain on weak lifters (60 N/m per m) settling under gravity: its static sag
  // is rho g / k = 65 mm where nothing presses, rho g / (k + k_p) = 3.5 mm under the
  // pressure of k_p = 1060 N/m per m (as stiff as the attached mesentery); stable at 1 ms
  // and settled after 20 s.
  const Vec3 g(0, 0, -9.81);
  const ColonModel m = pelvicChain(41, 60, g);
  ColonState s = makeColonState(m);
  RegionSupport r;
  r.anchor_q = m.q_rest;
  r.first_segment = 0;
  r.last_segment = m.n - 2;
  r.stiffness_N_per_m2 = 1000;
  r.damping_Ns_per_m2 = 20;
  for (int k = 0; k < 20000; ++k) {
    s.loads.clear();
    addRegionSupport(m, s, r, s.loads);
    stepColon(m, s, 1e-3);
    ASSERT_TRUE(s.solver_ok);
  }
  const double sag = -s.q(2, m.n / 2);
  EXPECT_NEAR(sag, 0.4 * 9.81 / 1060, 0.2e-3);
  EXPECT_LT(s.v.norm(), 1e-4);
  // Without the pressure the same chain sags 65 mm.
  ColonState free_state = makeColonState(m);
  for (int k = 0; k < 20000; ++k) stepColon(m, free_state, 1e-3);
  EXPECT_NEAR(-free_state.q(2, m.n / 2), 0.4 * 9.81 / 60, 3e-3);
}

TEST(AbdominalPressure, RampRisesHoldsAndFalls) {
  EXPECT_EQ(pressureRamp(0.99, 1.0, 5.0, 1.0), 0.0);
  EXPECT_EQ(pressureRamp(1.0, 1.0, 5.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(pressureRamp(1.5, 1.0, 5.0, 1.0), 0.5);
  EXPECT_EQ(pressureRamp(3.0, 1.0, 5.0, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(pressureRamp(4.75, 1.0, 5.0, 1.0), 0.25);
  EXPECT_EQ(pressureRamp(5.0, 1.0, 5.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(pressureRamp(1.5, 1.0, 2.0, 1.0), 0.5);  // overlapping ramps: the smaller
  EXPECT_EQ(pressureRamp(1.0, 1.0, 2.0, 0.0), 1.0);          // no ramp: a step
  EXPECT_EQ(pressureRamp(std::nan(""), 1.0, 2.0, 0.5), 0.0);
}

}  // namespace
}  // namespace colosim
