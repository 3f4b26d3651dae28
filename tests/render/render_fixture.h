// Small scenes for the render tests, written inline: a straight colon, an alpha loop.
#pragma once

#include <cmath>
#include <memory>

#include "core/colon_model.h"
#include "render/tube_mesh.h"

namespace colosim::test {

/// A colon model over the given control points (3 x n) [m] with a uniform radius [m].
inline ColonModel colonThrough(const Points& q, double radius_m) {
  return buildColonModelFromPoints(q, Eigen::VectorXd::Constant(q.cols(), radius_m), 0.4, 100.0, 1.0,
                                   Vec3::Zero(), std::make_shared<VoigtLaw>(28.9, 0.05));
}

/// A straight colon along +z from z = 0 to length_m, control points 15 mm apart.
inline ColonModel straightColon(double length_m = 0.36, double radius_m = 0.02) {
  const int n = static_cast<int>(std::round(length_m / 0.015)) + 1;
  Points q(3, n);
  for (int i = 0; i < n; ++i) q.col(i) = Vec3(0, 0, length_m * i / (n - 1));
  return colonThrough(q, radius_m);
}

/// An alpha loop in the x-z plane (seen from the front, y): up from the anus, a full
/// circle of radius loop_m crossing over itself, then on up. Points every ~step_m [m].
inline std::vector<Vec3> alphaLoopPath(double loop_m = 0.06, double step_m = 0.01) {
  std::vector<Vec3> p;
  const double pi = 3.14159265358979323846;
  // Lead-in up x = loop_m to the circle's rightmost point; the circle, centred at
  // (0, 0, h), comes back to that point, and the path leaves straight up. The circle
  // drifts in y (front to back) so the path crosses over, not through, itself.
  const double h = 0.12;
  for (double z = 0; z < h; z += step_m) p.push_back(Vec3(loop_m, -0.6 * loop_m * (z / h), z));
  const int k = static_cast<int>(2 * pi * loop_m / step_m);
  for (int i = 0; i <= k; ++i) {
    const double a = 2 * pi * i / k;
    p.push_back(Vec3(loop_m * std::cos(a), -0.6 * loop_m * std::cos(0.5 * a), h + loop_m * std::sin(a)));
  }
  for (double z = h + step_m; z < h + 0.1; z += step_m) p.push_back(Vec3(loop_m, 0.6 * loop_m, z));
  return p;
}

inline Points toPoints(const std::vector<Vec3>& v) {
  Points q(3, static_cast<int>(v.size()));
  for (size_t i = 0; i < v.size(); ++i) q.col(static_cast<int>(i)) = v[i];
  return q;
}

}  // namespace colosim::test
