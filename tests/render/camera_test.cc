#include "render/camera.h"
#include "core/numbers.h"

#include <gtest/gtest.h>

#include <Eigen/LU>  // determinant
#include <cmath>

namespace colosim {
namespace {

// Clip-space projection of a world point, then normalised device coordinates.
Eigen::Vector3f ndc(const Mat4f& proj_view, const Vec3& p) {
  const Eigen::Vector4f c = proj_view * Eigen::Vector4f(p.x(), p.y(), p.z(), 1);
  return c.head<3>() / c.w();
}

// (right, down, forward): a rotation, so a right-handed tip frame can be passed as is.
TEST(Camera, LookAlongIsARotationWithForwardAsThirdColumn) {
  const CameraPose p = lookAlong(Vec3(1, 2, 3), Vec3(0, 3, 4), Vec3::UnitZ());
  EXPECT_LT((p.R_WC.transpose() * p.R_WC - Mat3::Identity()).norm(), 1e-12);
  EXPECT_NEAR(p.R_WC.determinant(), 1.0, 1e-12);
  EXPECT_LT((p.R_WC.col(2) - Vec3(0, 0.6, 0.8)).norm(), 1e-12);
  EXPECT_LT(p.R_WC.col(1).dot(Vec3::UnitZ()), 0);  // down
  EXPECT_NO_THROW(checkCameraPose(p));
  CameraPose mirrored = p;
  mirrored.R_WC.col(1) *= -1;  // (right, up, forward): a reflection
  EXPECT_THROW(checkCameraPose(mirrored), std::invalid_argument);
  CameraPose skew = p;
  skew.R_WC(0, 0) += 0.01;
  EXPECT_THROW(checkCameraPose(skew), std::invalid_argument);
  skew = p;
  skew.p_WC_m.x() = std::nan("");
  EXPECT_THROW(checkCameraPose(skew), std::invalid_argument);
  // An up hint along forward still gives a valid pose.
  const CameraPose q = lookAlong(Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitZ());
  EXPECT_NEAR(q.R_WC.determinant(), 1.0, 1e-12);
}

// A point ahead of the camera lands at the image centre; one to the camera's right and
// up (-down) lands right and up on screen, and the patient's z (up hint) is up on screen;
// depth grows from near (-1) to far (+1).
TEST(Camera, ViewAndPerspectiveMapTheAxes) {
  const CameraPose p = lookAlong(Vec3(0.1, 0, 0), Vec3::UnitY(), Vec3::UnitZ());
  const Mat4f pv = perspectiveMatrix(60 * kPi / 180, 1.5, 0.01, 2.0) * viewMatrix(p);
  const Eigen::Vector3f centre = ndc(pv, Vec3(0.1, 0.5, 0));
  EXPECT_NEAR(centre.x(), 0, 1e-6);
  EXPECT_NEAR(centre.y(), 0, 1e-6);
  const Eigen::Vector3f ru = ndc(pv, Vec3(0.1, 0.5, 0) + 0.05 * p.R_WC.col(0) - 0.05 * p.R_WC.col(1));
  EXPECT_GT(ru.x(), 0);
  EXPECT_GT(ru.y(), 0);
  EXPECT_GT(ndc(pv, Vec3(0.1, 0.5, 0.05)).y(), 0);
  EXPECT_NEAR(ndc(pv, Vec3(0.1, 0.01, 0)).z(), -1, 1e-4);
  EXPECT_NEAR(ndc(pv, Vec3(0.1, 2.0, 0)).z(), 1, 1e-4);
  // The vertical half-angle reaches the top edge.
  const Vec3 top = Vec3(0.1, 1.0, 0) + std::tan(30 * kPi / 180) * Vec3::UnitZ();
  EXPECT_NEAR(ndc(pv, top).y(), 1, 1e-5);
}

TEST(Camera, DiagonalFieldOfView) {
  // At aspect 4:3 the diagonal is 5/3 of the height: tan(v/2) = tan(d/2) * 3/5.
  const double v = verticalFovFromDiagonal(140 * kPi / 180, 4.0 / 3.0);
  EXPECT_NEAR(std::tan(v / 2), std::tan(70 * kPi / 180) * 0.6, 1e-12);
}

TEST(OrbitCamera, OrbitPanZoom) {
  OrbitCamera c;
  c.target_m = Vec3(0.1, 0.2, 0.3);
  c.distance_m = 0.5;
  // Yaw 0, pitch 0: from anterior (-y in LPS), z up, the patient's left on screen right.
  CameraPose p = c.pose();
  EXPECT_LT((p.p_WC_m - Vec3(0.1, -0.3, 0.3)).norm(), 1e-12);
  EXPECT_LT((p.R_WC.col(2) - Vec3(0, 1, 0)).norm(), 1e-12);
  EXPECT_LT((p.R_WC.col(0) - Vec3(1, 0, 0)).norm(), 1e-12);
  // Orbiting keeps the distance to the target and looks at it.
  c.orbit(0.7, 0.4);
  p = c.pose();
  EXPECT_NEAR((p.p_WC_m - c.target_m).norm(), 0.5, 1e-12);
  EXPECT_LT(((c.target_m - p.p_WC_m).normalized() - p.R_WC.col(2)).norm(), 1e-12);
  c.orbit(0, 10);  // pitch is clamped short of the pole
  EXPECT_LT(c.pitch_rad, kPi / 2);
  // Pan moves the target across the view, not along it.
  const Vec3 before = c.target_m;
  p = c.pose();
  c.pan(0.1, -0.2);
  EXPECT_NEAR((c.target_m - before).dot(p.R_WC.col(2)), 0, 1e-12);
  EXPECT_GT((c.target_m - before).norm(), 0.01);
  c.zoom(0.5);
  EXPECT_NEAR(c.distance_m, 0.25, 1e-12);
  c.zoom(1e-6);
  EXPECT_NEAR(c.distance_m, 0.05, 1e-12);
}

TEST(OrbitCamera, FrameBoxSeesTheWholeBox) {
  const Vec3 lo(-0.15, -0.1, 0), hi(0.15, 0.1, 0.45);
  const OrbitCamera c = frameBox(lo, hi, 4.0 / 3.0);
  const Mat4f pv = perspectiveMatrix(c.fov_y_deg * kPi / 180, 4.0 / 3.0, 0.01, 10) * viewMatrix(c.pose());
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
    const Eigen::Vector3f n = ndc(pv, corner);
    EXPECT_LT(std::abs(n.x()), 1.0f) << k;
    EXPECT_LT(std::abs(n.y()), 1.0f) << k;
  }
}

}  // namespace
}  // namespace colosim
