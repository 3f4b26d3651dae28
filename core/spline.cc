#include "core/spline.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

namespace colosim {

const std::array<double, 4> Gauss4::node = {
    0.5 - 0.5 * 0.8611363115940526, 0.5 - 0.5 * 0.3399810435848563,
    0.5 + 0.5 * 0.3399810435848563, 0.5 + 0.5 * 0.8611363115940526};
const std::array<double, 4> Gauss4::weight = {
    0.5 * 0.3478548451374538, 0.5 * 0.6521451548625461, 0.5 * 0.6521451548625461,
    0.5 * 0.3478548451374538};

namespace {

// Raw Catmull-Rom weights of q_{j-1}, q_j, q_{j+1}, q_{j+2} (see spline.h).
std::array<double, 4> rawWeights(double p, int derivative) {
  const double p2 = p * p, p3 = p2 * p;
  switch (derivative) {
    case 0:
      return {0.5 * (-p3 + 2 * p2 - p), 0.5 * (3 * p3 - 5 * p2 + 2),
              0.5 * (-3 * p3 + 4 * p2 + p), 0.5 * (p3 - p2)};
    case 1:
      return {0.5 * (-3 * p2 + 4 * p - 1), 0.5 * (9 * p2 - 10 * p),
              0.5 * (-9 * p2 + 8 * p + 1), 0.5 * (3 * p2 - 2 * p)};
    default:
      return {0.5 * (-6 * p + 4), 0.5 * (18 * p - 10), 0.5 * (-18 * p + 8),
              0.5 * (6 * p - 2)};
  }
}

// 5-point Gauss-Legendre on [-1, 1].
constexpr std::array<double, 5> kGl5Node = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                            0.5384693101056831, 0.9061798459386640};
constexpr std::array<double, 5> kGl5Weight = {0.2369268850561891, 0.4786286704993665,
                                              0.5688888888888889, 0.4786286704993665,
                                              0.2369268850561891};

}  // namespace

Blend blend(int n, int segment, double p, int derivative) {
  assert(n >= 2 && segment >= 0 && segment <= n - 2);
  const std::array<double, 4> raw = rawWeights(p, derivative);
  Blend b;
  for (int k = 0; k < 4; ++k) {
    b.index[k] = segment - 1 + k;
    b.w[k] = raw[k];
  }
  // Fold the phantom points: q_{-1} = 2 q_0 - q_1 and q_n = 2 q_{n-1} - q_{n-2}.
  if (b.index[0] < 0) {
    const double w = b.w[0];
    b.index[0] = 0;  // the slot now holds q_0 with weight 2w ...
    b.w[0] = 2 * w;
    b.w[2] -= w;  // ... and -w on q_1 (slot 2 holds q_{segment+1} = q_1)
  }
  if (b.index[3] > n - 1) {
    const double w = b.w[3];
    b.index[3] = n - 1;  // slot holds q_{n-1} with 2w ...
    b.w[3] = 2 * w;
    b.w[1] -= w;  // ... and -w on q_{n-2} (slot 1 holds q_segment = q_{n-2})
  }
  return b;
}

Vec3 splinePoint(const Points& q, int segment, double p) {
  return apply(blend(static_cast<int>(q.cols()), segment, p, 0), q);
}

Vec3 splineTangent(const Points& q, int segment, double p) {
  return apply(blend(static_cast<int>(q.cols()), segment, p, 1), q);
}

Vec3 splineSecondDerivative(const Points& q, int segment, double p) {
  return apply(blend(static_cast<int>(q.cols()), segment, p, 2), q);
}

double segmentArclength(const Points& q, int segment, double a, double b) {
  constexpr int kSub = 4;
  const double h = (b - a) / kSub;
  double s = 0.0;
  for (int k = 0; k < kSub; ++k) {
    const double mid = a + (k + 0.5) * h;
    for (int g = 0; g < 5; ++g) {
      const double p = mid + 0.5 * h * kGl5Node[g];
      s += 0.5 * h * kGl5Weight[g] * splineTangent(q, segment, p).norm();
    }
  }
  return s;
}

double parameterAtArclength(const Points& q, int segment, double s_m) {
  const double total = segmentArclength(q, segment);
  if (s_m <= 0.0) return 0.0;
  if (s_m >= total) return 1.0;
  double lo = 0.0, hi = 1.0, p = s_m / total;
  for (int it = 0; it < 50; ++it) {
    const double f = segmentArclength(q, segment, 0.0, p) - s_m;
    if (std::abs(f) < 1e-12) break;
    if (f > 0) hi = p; else lo = p;
    const double speed = splineTangent(q, segment, p).norm();
    double next = speed > 0 ? p - f / speed : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    p = next;
  }
  return p;
}

namespace {

// The four blends segmentCubic() needs (the value and derivatives at p = 0, the second
// derivative at p = 1) depend on the segment's place among n control points only: built
// once per thread and n, the same values blend() gives (every cubic of every step used to
// build them again).
struct CubicBlends {
  Blend b[4];
};
const CubicBlends& cubicBlends(int n, int segment) {
  assert(n >= 2 && segment >= 0 && segment <= n - 2);
  thread_local int built_n = -1;
  thread_local std::vector<CubicBlends> table;
  if (built_n != n) {
    table.resize(static_cast<size_t>(n - 1));
    for (int j = 0; j + 1 < n; ++j)
      table[j] = {{blend(n, j, 0.0, 0), blend(n, j, 0.0, 1), blend(n, j, 0.0, 2), blend(n, j, 1.0, 2)}};
    built_n = n;
  }
  return table[static_cast<size_t>(segment)];
}

}  // namespace

SegmentCubic segmentCubic(const Points& q, int segment) {
  const int n = static_cast<int>(q.cols());
  // From the value and derivatives at p = 0 and the second derivative at p = 1.
  const CubicBlends& b = cubicBlends(n, segment);
  SegmentCubic c;
  c.c0 = apply(b.b[0], q);
  c.c1 = apply(b.b[1], q);
  const Vec3 d2a = apply(b.b[2], q);
  const Vec3 d2b = apply(b.b[3], q);
  c.c2 = 0.5 * d2a;
  c.c3 = (d2b - d2a) / 6.0;
  // c' = e1 + e2 p + e3 p^2 with e1 = c1, e2 = 2 c2, e3 = 3 c3; with d0 = c0 - x,
  // g = e1.d0 + (e1.c1 + e2.d0) p + (e1.c2 + e2.c1 + e3.d0) p^2 + (e1.c3 + e2.c2 + e3.c1) p^3
  //     + (e2.c3 + e3.c2) p^4 + e3.c3 p^5.
  const Vec3 e1 = c.c1, e2 = 2.0 * c.c2, e3 = 3.0 * c.c3;
  c.g_const[0] = e1.dot(c.c0);
  c.g_const[1] = e1.dot(c.c1) + e2.dot(c.c0);
  c.g_const[2] = e1.dot(c.c2) + e2.dot(c.c1) + e3.dot(c.c0);
  c.g_const[3] = e1.dot(c.c3) + e2.dot(c.c2) + e3.dot(c.c1);
  c.g_const[4] = e2.dot(c.c3) + e3.dot(c.c2);
  c.g_const[5] = e3.dot(c.c3);
  c.g_x[0] = e1;
  c.g_x[1] = e2;
  c.g_x[2] = e3;
  return c;
}

void segmentBounds(const Points& q, int segment, Vec3* lo, Vec3* hi) {
  const SegmentCubic c = segmentCubic(q, segment);
  // Bezier control points of the cubic: b0 = c(0), b1 = b0 + c'(0)/3, b2 = b3 - c'(1)/3, b3 = c(1).
  const Vec3 b0 = c.c0, b3 = c.at(1.0);
  const Vec3 b1 = b0 + c.c1 / 3.0;
  const Vec3 b2 = b3 - (c.c1 + 2.0 * c.c2 + 3.0 * c.c3) / 3.0;
  *lo = b0.cwiseMin(b1).cwiseMin(b2).cwiseMin(b3);
  *hi = b0.cwiseMax(b1).cwiseMax(b2).cwiseMax(b3);
}

double closestParameterOnCubic(const SegmentCubic& c, const Vec3& x, double p_lo, double p_hi,
                               double* distance_m) {
  p_lo = std::clamp(p_lo, 0.0, 1.0);
  p_hi = std::clamp(p_hi, p_lo, 1.0);
  // g(p) = c'(p) . (c(p) - x), a degree-5 polynomial: its coefficients from the parts
  // precomputed per segment (segmentCubic), then Horner.
  double g[6];
  g[0] = c.g_const[0] - c.g_x[0].dot(x);
  g[1] = c.g_const[1] - c.g_x[1].dot(x);
  g[2] = c.g_const[2] - c.g_x[2].dot(x);
  g[3] = c.g_const[3];
  g[4] = c.g_const[4];
  g[5] = c.g_const[5];
  auto G = [&](double p) { return g[0] + p * (g[1] + p * (g[2] + p * (g[3] + p * (g[4] + p * g[5])))); };
  auto dG = [&](double p) {
    return g[1] + p * (2 * g[2] + p * (3 * g[3] + p * (4 * g[4] + p * 5 * g[5])));
  };
  auto dist2 = [&](double p) { return (c.at(p) - x).squaredNorm(); };

  double best_p = p_lo, best = dist2(p_lo);
  const double d_hi = dist2(p_hi);
  if (d_hi < best) best = d_hi, best_p = p_hi;
  // Every minimum of the distance is a sign change of g from - to +: bracket them on 4
  // sub-intervals and refine each by Newton, bisecting whenever Newton leaves the bracket.
  // (A 1-2 cm segment rarely holds more than one minimum: two in one quarter would need
  // a point near the segment's centre of curvature.)
  constexpr int kSamples = 4;
  const double h = (p_hi - p_lo) / kSamples;
  if (h > 0) {
    double a = p_lo, ga = G(a);
    for (int k = 1; k <= kSamples; ++k) {
      const double b = (k == kSamples) ? p_hi : p_lo + k * h;
      const double gb = G(b);
      if (ga < 0 && gb >= 0) {
        double lo = a, hi = b, p = a - ga * (b - a) / (gb - ga);  // secant start
        for (int it = 0; it < 40; ++it) {
          const double gp = G(p);
          if (gp < 0) lo = p; else hi = p;
          const double slope = dG(p);
          double next = (slope > 0) ? p - gp / slope : 0.5 * (lo + hi);
          // Converged: test this before the bracket, since a converged Newton step may
          // land on the bracket end just moved to p, which would restart bisection.
          if (std::abs(next - p) < 1e-12) { p = std::clamp(next, lo, hi); break; }
          if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
          p = next;
        }
        const double d = dist2(p);
        if (d < best) best = d, best_p = p;
      }
      a = b;
      ga = gb;
    }
  }
  *distance_m = std::sqrt(best);
  return best_p;
}

ClosestPoint closestPointOnSegment(const Points& q, int segment, const Vec3& x, double p_lo,
                                   double p_hi) {
  const SegmentCubic c = segmentCubic(q, segment);
  ClosestPoint r;
  r.segment = segment;
  r.p = closestParameterOnCubic(c, x, p_lo, p_hi, &r.distance);
  r.point = c.at(r.p);
  return r;
}

ClosestPoint closestPointOnSpline(const Points& q, const Vec3& x) {
  ClosestPoint best;
  best.distance = -1.0;
  for (int j = 0; j + 1 < q.cols(); ++j) {
    const ClosestPoint c = closestPointOnSegment(q, j, x);
    if (best.distance < 0 || c.distance < best.distance) best = c;
  }
  return best;
}

}  // namespace colosim
