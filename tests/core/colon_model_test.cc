#include "core/colon_model.h"

#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "fixture.h"
#include "trainer/assets.h"

namespace colosim {
namespace {

Eigen::MatrixXd dense(const ScalarBand& a) {
  Eigen::MatrixXd d(a.size(), a.size());
  for (int i = 0; i < a.size(); ++i)
    for (int j = 0; j < a.size(); ++j) d(i, j) = a.at(i, j);
  return d;
}

ColonModel adultColon() {
  const Parameters p = loadParameters(test::asset("params/default.json"));
  return loadColonModel(test::asset("anatomy/adult.json"), p);
}

TEST(ColonModel, MassMatrixIsSymmetricPositiveDefiniteWithTotalRhoTimesLength) {
  const ColonModel m = adultColon();
  const Eigen::MatrixXd M = dense(m.mass);
  EXPECT_LT((M - M.transpose()).norm(), 1e-15);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
  EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
  EXPECT_NEAR(M.sum(), m.mass_per_length_kg_per_m * m.length_m(), 1e-12);
  // Banded: control points more than 3 apart do not couple.
  for (int i = 0; i < m.n; ++i)
    for (int j = 0; j < m.n; ++j) {
      if (std::abs(i - j) > 3) {
        EXPECT_EQ(M(i, j), 0.0);
      }
    }
}

TEST(ColonModel, SmallColonsAlsoHavePositiveDefiniteMass) {
  for (int n : {2, 3, 4, 5}) {
    Points q(3, n);
    for (int i = 0; i < n; ++i) q.col(i) = Vec3(0.015 * i, 0, 0);
    const ColonModel m = buildColonModelFromPoints(q, Eigen::VectorXd::Constant(n, 0.02), 0.4, 0, 0,
                                                   Vec3::Zero(), std::make_shared<VoigtLaw>(28.9, 0.05));
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(dense(m.mass));
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0) << n;
    EXPECT_NEAR(dense(m.mass).sum(), 0.4 * 0.015 * (n - 1), 1e-15);
  }
}

TEST(ColonModel, UniformMesenteryIsProportionalToMass) {
  Points q(3, 20);
  for (int i = 0; i < 20; ++i) q.col(i) = Vec3(0.015 * i, 0.01 * std::sin(i), 0);
  const ColonModel m = buildColonModelFromPoints(q, Eigen::VectorXd::Constant(20, 0.02), 0.4, 500, 10,
                                                 Vec3::Zero(), std::make_shared<VoigtLaw>(28.9, 0.05));
  EXPECT_LT((dense(m.mesentery_K) - (500 / 0.4) * dense(m.mass)).norm(), 1e-9);
  EXPECT_LT((dense(m.mesentery_C) - (10 / 0.4) * dense(m.mass)).norm(), 1e-11);
}

TEST(ColonModel, AdultAnatomyHasTheExpectedShape) {
  const ColonModel m = adultColon();
  EXPECT_GT(m.length_m(), 1.31);
  EXPECT_LT(m.length_m(), 1.90);
  for (int j = 0; j + 1 < m.n; ++j) {
    EXPECT_GT(m.rest_length_m(j), 0.010);
    EXPECT_LT(m.rest_length_m(j), 0.020);
  }
  // Attached where the anatomy is attached, free in the sigmoid and transverse colon.
  for (int j = 0; j + 1 < m.n; ++j) {
    const std::string& region = m.region_names[m.segment_region[j]];
    const bool free_region = region == "sigmoid" || region == "transverse";
    EXPECT_EQ(m.region_mesentery[m.segment_region[j]], free_region ? "free" : "attached") << region;
  }
  EXPECT_EQ(m.region_names[m.segment_region.front()], "rectum");
  EXPECT_EQ(m.region_names[m.segment_region.back()], "caecum");
  EXPECT_LT(m.q_rest.col(0).norm(), 1e-12);  // starts at the anus
  EXPECT_GT(m.radius_m.minCoeff(), 0.01);
  // Left lateral by default: gravity towards the patient's left (+x).
  EXPECT_NEAR(m.gravity_m_per_s2.x(), 9.81, 1e-12);
}

TEST(ColonModel, AdultBendsAreWiderThanTheLumen) {
  // A bend tighter than the lumen radius would fold the wall through itself.
  const ColonModel m = adultColon();
  for (int j = 0; j + 1 < m.n; ++j) {
    for (double p : {0.0, 0.25, 0.5, 0.75}) {
      const Vec3 d1 = splineTangent(m.q_rest, j, p), d2 = splineSecondDerivative(m.q_rest, j, p);
      const double curvature = d1.cross(d2).norm() / std::pow(d1.norm(), 3);
      EXPECT_LT(curvature * m.radiusAt(j, p), 1.0)
          << m.region_names[m.segment_region[j]] << " segment " << j << " p " << p << ": bend radius "
          << 1 / curvature << " m, lumen radius " << m.radiusAt(j, p) << " m";
    }
  }
}

TEST(ColonModel, SpacingIsALoadTimeOption) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  const Anatomy a = loadAnatomy(test::asset("anatomy/adult.json"));
  p.colon.control_point_spacing_m = 0.01;
  const ColonModel fine = buildColonModel(a, p.colon);
  p.colon.control_point_spacing_m = 0.02;
  const ColonModel coarse = buildColonModel(a, p.colon);
  EXPECT_GT(fine.n, 1.8 * coarse.n);
  EXPECT_NEAR(fine.length_m(), coarse.length_m(), 2e-3);
}

TEST(ColonModel, GravityFollowsThePatientPosition) {
  EXPECT_EQ(gravityForPosition("supine", 9.81), Vec3(0, 9.81, 0));  // LPS: y posterior
  EXPECT_EQ(gravityForPosition("right_lateral", 9.81), Vec3(-9.81, 0, 0));
  EXPECT_THROW(gravityForPosition("standing", 9.81), std::invalid_argument);
}

// Haustral folds (issue 21, pleating): the contact wall narrowed by the fold depth at the
// control point nearest each fold, every fold period of rest arclength, never in or next to
// the rectum; the anatomy's radius kept beside it for the renderer, which draws its own folds.
TEST(ColonModel, HaustralFoldsNarrowTheWallEveryPeriodOutsideTheRectum) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  p.colon.haustral_fold_depth = 0.25;
  const ColonModel folded = loadColonModel(test::asset("anatomy/adult_pelvic_rectum.json"), p);
  p.colon.haustral_fold_depth = 0.0;
  const ColonModel smooth = loadColonModel(test::asset("anatomy/adult_pelvic_rectum.json"), p);
  EXPECT_EQ(folded.smooth_radius_m, smooth.radius_m);
  EXPECT_EQ(smooth.radius_m, smooth.smooth_radius_m);
  std::vector<double> fold_s;
  for (int k = 0; k < folded.n; ++k) {
    if (folded.radius_m(k) == folded.smooth_radius_m(k)) continue;
    EXPECT_NEAR(folded.radius_m(k), (1 - 0.25) * folded.smooth_radius_m(k), 1e-15);
    for (int j : {k - 1, k})
      EXPECT_NE(folded.region_names[folded.segment_region[j]], "rectum") << "control point " << k;
    fold_s.push_back(folded.s_rest_m(k));
  }
  ASSERT_GT(fold_s.size(), 40u);
  const double spacing = folded.length_m() / (folded.n - 1);
  for (size_t i = 1; i < fold_s.size(); ++i)
    EXPECT_NEAR(fold_s[i] - fold_s[i - 1], p.colon.haustral_fold_period_m, spacing + 1e-9) << "fold " << i;
  // Outside the rectum no stretch longer than a period goes without a fold.
  EXPECT_LT(fold_s.back(), folded.length_m());
}

}  // namespace
}  // namespace colosim
