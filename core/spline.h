// Catmull-Rom spline math (paper section 2.1, eq. 1), as stateless free functions.
//
// A spline over n >= 2 control points q_0..q_{n-1} (a 3 x n matrix, metres) has
// n - 1 segments; segment j runs from q_j (p = 0) to q_{j+1} (p = 1) and is
//   M_j(p) = sum_i b_i^j(p) q_i                                        (eq. 1)
// with the uniform Catmull-Rom blending functions of q_{j-1}, q_j, q_{j+1}, q_{j+2}:
//   b_{j-1} = (-p^3 + 2p^2 - p) / 2      b_j     = (3p^3 - 5p^2 + 2) / 2
//   b_{j+1} = (-3p^3 + 4p^2 + p) / 2     b_{j+2} = (p^3 - p^2) / 2
// At the two ends the missing neighbour is the phantom point q_{-1} = 2 q_0 - q_1
// (and q_n = 2 q_{n-1} - q_{n-2}), folded into the real control points, so every
// point of the curve stays a linear combination of real control points, the
// blending functions still sum to 1, and the end tangent is q_1 - q_0.
#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace colosim {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
/// Control points, one per column (3 x n) [m].
using Points = Eigen::Matrix3Xd;

/// Blending weights of one spline point: weight w[k] multiplies control point index[k].
/// Indices may repeat at the two end segments (the folded phantom point); consumers
/// accumulate. All indices lie in [segment - 1, segment + 2] clamped to [0, n - 1].
struct Blend {
  std::array<int, 4> index{};
  std::array<double, 4> w{};
};

/// Weights of the control points at parameter p in [0, 1] of segment `segment`
/// (0 <= segment <= n - 2) of a spline over n control points.
/// derivative: 0 for the position, 1 for dM/dp, 2 for d2M/dp2.
Blend blend(int n, int segment, double p, int derivative = 0);

/// Applies a blend to control points: sum_k w[k] q.col(index[k]).
inline Vec3 apply(const Blend& b, const Points& q) {
  return b.w[0] * q.col(b.index[0]) + b.w[1] * q.col(b.index[1]) +
         b.w[2] * q.col(b.index[2]) + b.w[3] * q.col(b.index[3]);
}

/// Position M_j(p) [m], first derivative dM/dp [m] and second derivative [m].
Vec3 splinePoint(const Points& q, int segment, double p);
Vec3 splineTangent(const Points& q, int segment, double p);
Vec3 splineSecondDerivative(const Points& q, int segment, double p);

/// Arclength of segment `segment` between p = a and p = b [m]
/// (Gauss-Legendre, 4 sub-intervals of 5 points: exact to ~1e-9 relative on the
/// smooth curves we use).
double segmentArclength(const Points& q, int segment, double a = 0.0, double b = 1.0);

/// Parameter p in [0, 1] where the arclength from p = 0 of the segment reaches s [m]
/// (clamped to the segment). Safeguarded Newton on the arclength.
double parameterAtArclength(const Points& q, int segment, double s_m);

/// Result of a closest-point query on one segment.
struct ClosestPoint {
  int segment = 0;
  double p = 0.0;              ///< parameter on the segment, always in [0, 1]
  Vec3 point = Vec3::Zero();   ///< M_j(p) [m]
  double distance = 0.0;       ///< |x - M_j(p)| [m]
};

/// Segment j as a cubic polynomial c(p) = c0 + c1 p + c2 p^2 + c3 p^3 [m]: computed once
/// per step and shared by every closest-point query on that segment.
struct SegmentCubic {
  Vec3 c0 = Vec3::Zero(), c1 = Vec3::Zero(), c2 = Vec3::Zero(), c3 = Vec3::Zero();
  /// g(p) = c'(p) . (c(p) - x) = sum_k (g_const[k] - g_x[k] . x) p^k: the parts of its
  /// coefficients that do not depend on the query point x, computed once per segment.
  double g_const[6] = {0, 0, 0, 0, 0, 0};
  Vec3 g_x[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  ///< for k = 0, 1, 2 (c', 2 c2, 3 c3 ... )
  Vec3 at(double p) const { return c0 + p * (c1 + p * (c2 + p * c3)); }
};
SegmentCubic segmentCubic(const Points& q, int segment);

/// Axis-aligned bounds of a segment from its Bezier control points (the curve lies in
/// their convex hull) [m].
void segmentBounds(const Points& q, int segment, Vec3* lo, Vec3* hi);

/// Closest point of the cubic to x for p in [p_lo, p_hi] (see closestPointOnSegment).
/// Returns p [-] and writes the distance [m].
double closestParameterOnCubic(const SegmentCubic& c, const Vec3& x, double p_lo, double p_hi,
                               double* distance_m);

/// Closest point of segment `segment` to x, restricted to p in [p_lo, p_hi] within [0, 1].
/// Samples the squared distance at 8 sub-intervals, refines every bracketed minimum
/// by safeguarded Newton (a bisection step whenever Newton would leave the bracket)
/// and compares with the interval ends, so p never leaves [p_lo, p_hi].
ClosestPoint closestPointOnSegment(const Points& q, int segment, const Vec3& x,
                                   double p_lo = 0.0, double p_hi = 1.0);

/// Closest point of the whole spline to x: the paper's scan over every segment.
ClosestPoint closestPointOnSpline(const Points& q, const Vec3& x);

/// Gauss-Legendre nodes on [0, 1] and weights summing to 1, for K = 4 points
/// (exact for polynomials of degree 7: products of two cubic blending functions).
struct Gauss4 {
  static constexpr int kCount = 4;
  static const std::array<double, 4> node;
  static const std::array<double, 4> weight;
};

}  // namespace colosim
