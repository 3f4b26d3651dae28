// Rotation helpers: the shared-trigonometry log and Jacobian agree with the two separate
// functions, across the angles where each switches formula.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rotation.h"

namespace colosim {
namespace {

TEST(Rotation, LogWithJacobianAgreesWithLogAndJacobianApart) {
  const Vec3 axes[] = {Vec3(1, 0, 0), Vec3(0.3, -0.8, 0.52).normalized(), Vec3(-0.1, 0.2, 0.97).normalized()};
  const double angles[] = {0.0, 1e-7, 5e-5, 1e-4, 2e-4, 0.01, 0.3, 1.0, 2.0, 3.0, M_PI - 1e-5, M_PI - 1e-7};
  for (const Vec3& axis : axes)
    for (double t : angles) {
      const Mat3 R = expSO3(t * axis);
      Mat3 J;
      const Vec3 w = logSO3WithJacobian(R, &J);
      const Vec3 w_apart = logSO3(R);
      EXPECT_LT((w - w_apart).norm(), 1e-12 * (1 + t)) << "angle " << t;
      EXPECT_LT((J - rightJacobianInverse(w_apart)).norm(), 1e-9) << "angle " << t;
    }
}

// Jr^{-1} is the inverse of the right Jacobian: log(exp(w) exp(d)) = w + Jr^{-1}(w) d to
// first order in d.
TEST(Rotation, JacobianMapsARightPerturbationToTheLog) {
  const Vec3 w(0.4, -1.1, 0.7);
  Mat3 J;
  logSO3WithJacobian(expSO3(w), &J);
  const double h = 1e-6;
  for (int c = 0; c < 3; ++c) {
    const Vec3 d = h * Vec3::Unit(c);
    const Vec3 fd = (logSO3(expSO3(w) * expSO3(d)) - logSO3(expSO3(w) * expSO3(-d))) / (2 * h);
    EXPECT_LT((fd - J.col(c)).norm(), 1e-7) << c;
  }
}

}  // namespace
}  // namespace colosim
