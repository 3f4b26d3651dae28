#include "core/spline.h"

#include <random>

#include <gtest/gtest.h>
#include "tests/random_vec3.h"

namespace colosim {
namespace {

Points randomPoints(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  Points q(3, n);
  for (int i = 0; i < n; ++i) q.col(i) = Vec3(0.05 * i, 0, 0) + test::randomVec3(u, rng);
  return q;
}

TEST(Spline, InterpolatesControlPoints) {
  std::mt19937 rng(1);
  const Points q = randomPoints(7, rng);
  for (int j = 0; j + 1 < 7; ++j) {
    EXPECT_LT((splinePoint(q, j, 0.0) - q.col(j)).norm(), 1e-15);
    EXPECT_LT((splinePoint(q, j, 1.0) - q.col(j + 1)).norm(), 1e-15);
  }
}

TEST(Spline, BlendingIsAPartitionOfUnityAtEveryEnd) {
  for (int n : {2, 3, 4, 9}) {
    for (int j = 0; j + 1 < n; ++j) {
      for (double p : {0.0, 0.2, 0.5, 0.77, 1.0}) {
        const Blend b0 = blend(n, j, p, 0), b1 = blend(n, j, p, 1), b2 = blend(n, j, p, 2);
        double s0 = 0, s1 = 0, s2 = 0;
        for (int k = 0; k < 4; ++k) {
          s0 += b0.w[k];
          s1 += b1.w[k];
          s2 += b2.w[k];
          EXPECT_GE(b0.index[k], 0);
          EXPECT_LT(b0.index[k], n);
          EXPECT_LE(std::abs(b0.index[k] - j), 2);
        }
        EXPECT_NEAR(s0, 1.0, 1e-14);
        EXPECT_NEAR(s1, 0.0, 1e-14);
        EXPECT_NEAR(s2, 0.0, 1e-14);
      }
    }
  }
}

TEST(Spline, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(2);
  const Points q = randomPoints(6, rng);
  const double h = 1e-6;
  for (int j = 0; j < 5; ++j) {
    for (double p : {0.1, 0.5, 0.9}) {
      const Vec3 fd1 = (splinePoint(q, j, p + h) - splinePoint(q, j, p - h)) / (2 * h);
      const Vec3 fd2 = (splineTangent(q, j, p + h) - splineTangent(q, j, p - h)) / (2 * h);
      EXPECT_LT((fd1 - splineTangent(q, j, p)).norm(), 1e-7);
      EXPECT_LT((fd2 - splineSecondDerivative(q, j, p)).norm(), 1e-6);
    }
  }
}

TEST(Spline, EndTangentsFollowThePhantomPoints) {
  std::mt19937 rng(3);
  const Points q = randomPoints(5, rng);
  EXPECT_LT((splineTangent(q, 0, 0.0) - (q.col(1) - q.col(0))).norm(), 1e-14);
  EXPECT_LT((splineTangent(q, 3, 1.0) - (q.col(4) - q.col(3))).norm(), 1e-14);
}

TEST(Spline, TangentIsContinuousAcrossSegments) {
  std::mt19937 rng(4);
  const Points q = randomPoints(6, rng);
  for (int j = 0; j + 2 < 6; ++j)
    EXPECT_LT((splineTangent(q, j, 1.0) - splineTangent(q, j + 1, 0.0)).norm(), 1e-14);
}

TEST(Spline, ArclengthOfStraightAndCircularCurves) {
  Points line(3, 5);
  for (int i = 0; i < 5; ++i) line.col(i) = Vec3(0.02 * i, 0, 0);
  EXPECT_NEAR(segmentArclength(line, 2), 0.02, 1e-15);

  // Points on a circle of radius 0.1 m every 10 degrees: the spline is close to the arc.
  const int n = 37;
  Points circle(3, n);
  for (int i = 0; i < n; ++i) {
    const double a = i * M_PI / 18;
    circle.col(i) = Vec3(0.1 * std::cos(a), 0.1 * std::sin(a), 0);
  }
  EXPECT_NEAR(segmentArclength(circle, 10), 0.1 * M_PI / 18, 2e-6);
}

TEST(Spline, ParameterAtArclengthInvertsArclength) {
  std::mt19937 rng(5);
  const Points q = randomPoints(5, rng);
  for (double p : {0.0, 0.13, 0.5, 0.91, 1.0}) {
    const double s = segmentArclength(q, 1, 0.0, p);
    EXPECT_NEAR(parameterAtArclength(q, 1, s), p, 1e-9);
  }
}

TEST(Spline, ClosestPointMatchesDenseSamplingAndStaysInRange) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-0.2, 0.4);
  const Points q = randomPoints(8, rng);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 x = test::randomVec3(u, rng);
    const int j = trial % 7;
    const ClosestPoint c = closestPointOnSegment(q, j, x);
    ASSERT_GE(c.p, 0.0);
    ASSERT_LE(c.p, 1.0);
    double best = 1e9;
    for (int k = 0; k <= 20000; ++k) best = std::min(best, (splinePoint(q, j, k / 20000.0) - x).norm());
    EXPECT_LE(c.distance, best + 1e-9);
    EXPECT_NEAR((c.point - x).norm(), c.distance, 1e-15);
  }
}

TEST(Spline, ClosestPointRespectsASubInterval) {
  Points q(3, 4);
  for (int i = 0; i < 4; ++i) q.col(i) = Vec3(0.1 * i, 0, 0);
  const ClosestPoint c = closestPointOnSegment(q, 1, Vec3(0.15, 0.02, 0), 0.7, 0.9);
  EXPECT_DOUBLE_EQ(c.p, 0.7);
  const ClosestPoint all = closestPointOnSpline(q, Vec3(0.15, 0.02, 0));
  EXPECT_EQ(all.segment, 1);
  EXPECT_NEAR(all.p, 0.5, 1e-9);
  EXPECT_NEAR(all.distance, 0.02, 1e-12);
}

TEST(Spline, Gauss4IntegratesDegreeSevenExactly) {
  double s = 0;
  for (int g = 0; g < Gauss4::kCount; ++g) s += Gauss4::weight[g] * std::pow(Gauss4::node[g], 7);
  EXPECT_NEAR(s, 1.0 / 8.0, 1e-15);
}

}  // namespace
}  // namespace colosim
