#include "render/frames.h"

#include <algorithm>
#include <cmath>

namespace colosim {

Vec3 anyPerpendicular(const Vec3& t) {
  // Cross with the coordinate axis least aligned with t: never degenerate.
  Vec3 axis = Vec3::UnitX();
  if (std::abs(t.y()) < std::abs(t.x()) && std::abs(t.y()) <= std::abs(t.z()))
    axis = Vec3::UnitY();
  else if (std::abs(t.z()) < std::abs(t.x()))
    axis = Vec3::UnitZ();
  return t.cross(axis).normalized();
}

Vec3 initialNormal(const Vec3& d1, const Vec3& d2) {
  const Vec3 t = d1.normalized();
  // Principal normal = the part of d2 normal to t; the curvature is |n| / |d1|^2, so the
  // start counts as curved when |n| / |d1| (curvature times the parameter's length scale)
  // exceeds 1e-9. A straight start (d2 parallel to t, or zero) takes any perpendicular.
  const Vec3 n = d2 - d2.dot(t) * t;
  if (n.norm() > 1e-9 * d1.norm()) return n.normalized();
  return anyPerpendicular(t);
}

void rotationMinimisingFrames(const std::vector<Vec3>& x, const std::vector<Vec3>& tangent, const Vec3& r0,
                              std::vector<CurveFrame>& frames) {
  const size_t n = x.size();
  frames.resize(n);
  if (n == 0) return;
  CurveFrame f;
  f.t = tangent[0].normalized();
  Vec3 r = r0 - r0.dot(f.t) * f.t;
  f.r = r.norm() > 1e-12 ? r.normalized() : anyPerpendicular(f.t);
  f.s = f.t.cross(f.r);
  frames[0] = f;
  for (size_t i = 0; i + 1 < n; ++i) {
    const CurveFrame& a = frames[i];
    CurveFrame b;
    b.t = tangent[i + 1].normalized();
    const Vec3 v1 = x[i + 1] - x[i];
    const double c1 = v1.squaredNorm();
    Vec3 rL = a.r, tL = a.t;
    if (c1 > 1e-24) {  // coincident points: skip the first reflection
      rL = a.r - (2.0 / c1) * v1.dot(a.r) * v1;
      tL = a.t - (2.0 / c1) * v1.dot(a.t) * v1;
    }
    const Vec3 v2 = b.t - tL;
    const double c2 = v2.squaredNorm();
    Vec3 rn = c2 > 1e-24 ? Vec3(rL - (2.0 / c2) * v2.dot(rL) * v2) : rL;
    // Re-orthonormalise against rounding (keeps the frame exact over thousands of steps).
    rn -= rn.dot(b.t) * b.t;
    b.r = rn.norm() > 1e-12 ? rn.normalized() : anyPerpendicular(b.t);
    b.s = b.t.cross(b.r);
    frames[i + 1] = b;
  }
}

double frameRotationAngle(const CurveFrame& a, const CurveFrame& b) {
  Mat3 A, B;
  A << a.r, a.s, a.t;
  B << b.r, b.s, b.t;
  const double c = std::clamp(((A.transpose() * B).trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c);
}

}  // namespace colosim
