#include "render/camera.h"

#include <Eigen/LU>  // determinant
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/numbers.h"
#include "render/frames.h"

namespace colosim {

CameraPose lookAlong(const Vec3& position_m, const Vec3& forward, const Vec3& up_hint) {
  const Vec3 f = forward.normalized();
  Vec3 up = up_hint - up_hint.dot(f) * f;
  if (up.norm() < 1e-9 * std::max(up_hint.norm(), 1e-300)) up = anyPerpendicular(f);
  up.normalize();
  CameraPose pose;
  pose.p_WC_m = position_m;
  pose.R_WC.col(0) = f.cross(up);  // right = forward x up
  pose.R_WC.col(1) = -up;          // down: (right, down, forward) is right-handed
  pose.R_WC.col(2) = f;
  return pose;
}

void checkCameraPose(const CameraPose& pose) {
  if (!pose.p_WC_m.allFinite() || !pose.R_WC.allFinite())
    throw std::invalid_argument("render: camera pose is not finite");
  if ((pose.R_WC.transpose() * pose.R_WC - Mat3::Identity()).norm() > 1e-6)
    throw std::invalid_argument("render: camera R_WC is not orthonormal");
  if (pose.R_WC.determinant() < 0)
    throw std::invalid_argument(
        "render: camera R_WC is a reflection; its columns must be right, down, forward");
}

void OrbitCamera::orbit(double dyaw_rad, double dpitch_rad) {
  yaw_rad = std::remainder(yaw_rad + dyaw_rad, 2 * kPi);
  pitch_rad = std::clamp(pitch_rad + dpitch_rad, -0.49 * kPi, 0.49 * kPi);
}

void OrbitCamera::pan(double dx, double dy) {
  const CameraPose p = pose();
  const double h = 2 * distance_m * std::tan(0.5 * fov_y_deg * kPi / 180);
  target_m += h * (dx * p.R_WC.col(0) - dy * p.R_WC.col(1));  // col(1) points down
}

void OrbitCamera::zoom(double factor) { distance_m = std::clamp(distance_m * factor, 0.05, 10.0); }

CameraPose OrbitCamera::pose() const {
  // Eye direction from the target: anterior (-y in the LPS patient frame) rotated by yaw
  // about z, raised by pitch. From the front, the patient's left (+x) is on screen right.
  const Vec3 dir(std::sin(yaw_rad) * std::cos(pitch_rad), -std::cos(yaw_rad) * std::cos(pitch_rad),
                 std::sin(pitch_rad));
  return lookAlong(target_m + distance_m * dir, -dir, Vec3::UnitZ());
}

OrbitCamera frameBox(const Vec3& lo_m, const Vec3& hi_m, double aspect) {
  OrbitCamera c;
  c.target_m = 0.5 * (lo_m + hi_m);
  const Vec3 half = 0.5 * (hi_m - lo_m);
  // Seen from the front: x across, z up; fit both with a 15 % margin.
  const double half_h = 1.15 * std::max(half.z(), half.x() / std::max(aspect, 1e-6));
  const double t = std::tan(0.5 * c.fov_y_deg * kPi / 180);
  c.distance_m = std::max(half_h / t + half.y(), 0.05);
  return c;
}

Mat4f viewMatrix(const CameraPose& pose) {
  // GL camera axes: x = right, y = up = -down, z = -forward.
  Mat3 R_CW;
  R_CW.row(0) = pose.R_WC.col(0).transpose();
  R_CW.row(1) = -pose.R_WC.col(1).transpose();
  R_CW.row(2) = -pose.R_WC.col(2).transpose();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = R_CW;
  m.topRightCorner<3, 1>() = -R_CW * pose.p_WC_m;
  return m.cast<float>();
}

Mat4f perspectiveMatrix(double fov_y_rad, double aspect, double near_m, double far_m) {
  const double f = 1.0 / std::tan(0.5 * fov_y_rad);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (far_m + near_m) / (near_m - far_m);
  m(2, 3) = 2 * far_m * near_m / (near_m - far_m);
  m(3, 2) = -1;
  return m.cast<float>();
}

double verticalFovFromDiagonal(double fov_diagonal_rad, double aspect) {
  // tan(fov_d / 2) spans the half diagonal; the half height is 1 / sqrt(1 + aspect^2) of it.
  return 2 * std::atan(std::tan(0.5 * fov_diagonal_rad) / std::sqrt(1 + aspect * aspect));
}

}  // namespace colosim
