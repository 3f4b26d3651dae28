// Cameras of the two views (pure math, no GL): the onboard camera at the scope tip and
// the orbiting global camera, and the 4 x 4 matrices GL needs.
#pragma once

#include <Eigen/Core>

#include "core/spline.h"

namespace colosim {

using Mat4f = Eigen::Matrix4f;

/// A camera pose in the world (patient) frame W: p_WC its position [m], R_WC a rotation
/// (det +1) whose columns are the camera's right, down and forward axes in W (forward =
/// the scope tip axis for the onboard camera). This is the optical-frame convention of
/// OpenCV and ROS; (right, up, forward) cannot be a rotation: it is a left-handed triad.
struct CameraPose {
  Vec3 p_WC_m = Vec3::Zero();
  Mat3 R_WC = Mat3::Identity();
};

/// Throws std::invalid_argument unless the pose is finite and R_WC is a rotation (to
/// 1e-6): a reflection would silently mirror the image.
void checkCameraPose(const CameraPose& pose);

/// A pose at `position_m` looking along `forward` with `up_hint` roughly up on screen (not
/// parallel to forward; a perpendicular is chosen if it is).
CameraPose lookAlong(const Vec3& position_m, const Vec3& forward, const Vec3& up_hint);

/// Onboard optics: a wide-angle colonoscope lens lit by a light at the tip.
struct OnboardOptics {
  double fov_diagonal_deg = 140;  ///< field of view across the image diagonal [deg]
  double near_m = 0.0001;         ///< near clip plane [m]: the lens may come this close to the wall (see docs)
  double far_m = 0.3;             ///< far clip plane [m]; the tip light fades out before it
  double light_ref_m = 0.02;      ///< distance at which the tip light gives unit irradiance [m]
  double exposure = 2.5;          ///< scales the irradiance before tone mapping [-]
  /// Barrel distortion of an equidistant lens, applied per vertex (the mesh is dense):
  /// exact at the vertices, and good while the wall beside the lens is farther than a few
  /// mm, which the scope's own radius (6.5 mm) ensures. false: rectilinear perspective.
  bool barrel_distortion = true;
  /// Draws the view at this fraction of the viewport's size in each direction and
  /// stretches it onto the viewport (bilinear): 0.7 costs about half the fragment work.
  /// In [0.25, 1]; 1 draws at full size (image export). colosim train lowers it.
  double render_scale = 1.0;
  /// Draw only the strips of the colon the view can see, and far ones coarser
  /// (render/tube_mesh.h visibleDetailIndices). false: every strip at full detail (the
  /// reference the cull and the detail levels are tested against).
  bool reduce_detail = true;
};

/// Orbit camera of the global view: looks at `target_m` from `distance_m` away, from the
/// direction given by yaw (about the patient's cranial z axis, 0 = from anterior, -y in LPS) and
/// pitch (elevation above the x-y plane) [rad]. Orthographic-like narrow perspective.
struct OrbitCamera {
  Vec3 target_m = Vec3::Zero();
  double yaw_rad = 0;
  double pitch_rad = 0;
  double distance_m = 0.8;
  double fov_y_deg = 30;

  void orbit(double dyaw_rad, double dpitch_rad);
  /// Moves the target in the view plane by (dx, dy) fractions of the visible height.
  void pan(double dx, double dy);
  /// Multiplies the distance by `factor` (< 1 zooms in), kept in [0.05, 10] m.
  void zoom(double factor);
  CameraPose pose() const;
};

/// An orbit camera framing the axis-aligned box [lo, hi] [m] from the front (anterior).
OrbitCamera frameBox(const Vec3& lo_m, const Vec3& hi_m, double aspect);

/// World-to-camera matrix of GL (camera looks down -z, y up).
Mat4f viewMatrix(const CameraPose& pose);
/// Perspective projection with vertical field of view fov_y_rad and aspect w / h.
Mat4f perspectiveMatrix(double fov_y_rad, double aspect, double near_m, double far_m);
/// Vertical field of view [rad] for a diagonal field of view [rad] and aspect w / h.
double verticalFovFromDiagonal(double fov_diagonal_rad, double aspect);

}  // namespace colosim
