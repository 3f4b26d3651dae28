// Rotation-minimising frames along a sampled curve (pure math, no GL).
//
// The Frenet frame flips at inflection points and is undefined where the curve is
// straight, so the tube meshes use rotation-minimising frames (RMF) computed by the
// double-reflection method of Wang, Juettler, Zheng & Liu, "Computation of rotation
// minimizing frames", ACM TOG 27(1), 2008, algorithm of section 4:
//   v1 = x_{i+1} - x_i,  c1 = v1.v1
//   rL = r_i - (2/c1)(v1.r_i) v1,   tL = t_i - (2/c1)(v1.t_i) v1     (reflection 1)
//   v2 = t_{i+1} - tL,  c2 = v2.v2
//   r_{i+1} = rL - (2/c2)(v2.rL) v2,   s_{i+1} = t_{i+1} x r_{i+1}   (reflection 2)
// Its error per step is O(h^4); the frames neither twist nor flip.
#pragma once

#include <Eigen/Geometry>  // cross products
#include <vector>

#include "core/spline.h"

namespace colosim {

/// An orthonormal frame at one point of a curve: t the unit tangent, r and s two unit
/// normals with s = t x r (right-handed: (r, s, t) is a rotation).
struct CurveFrame {
  Vec3 t = Vec3::UnitZ();
  Vec3 r = Vec3::UnitX();
  Vec3 s = Vec3::UnitY();
};

/// A unit vector perpendicular to the unit vector t (the axis least aligned with t,
/// orthogonalised): the fallback normal on a straight start.
Vec3 anyPerpendicular(const Vec3& t);

/// Initial normal r_0 at a curve start with first derivative d1 and second derivative d2
/// (any parameterisation): the Frenet principal normal where the curvature is non-zero
/// (relative test, see frames.cc), else anyPerpendicular(t).
Vec3 initialNormal(const Vec3& d1, const Vec3& d2);

/// Rotation-minimising frames at points x (m) with tangents tangent (any non-zero length;
/// normalised here), started from r0 (projected onto the plane normal to the first
/// tangent and normalised). x and tangent have the same size >= 1.
/// [out] frames, resized to x.size().
void rotationMinimisingFrames(const std::vector<Vec3>& x, const std::vector<Vec3>& tangent, const Vec3& r0,
                              std::vector<CurveFrame>& frames);

/// Rotation angle [rad] between two frames (angle of the rotation taking a to b).
double frameRotationAngle(const CurveFrame& a, const CurveFrame& b);

}  // namespace colosim
