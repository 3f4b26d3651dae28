#include "core/spline.h"

#include <algorithm>
#include <cassert>
#include <cmath>

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

ClosestPoint closestPointOnSegment(const Points& q, int segment, const Vec3& x, double p_lo,
                                   double p_hi) {
  const int n = static_cast<int>(q.cols());
  p_lo = std::clamp(p_lo, 0.0, 1.0);
  p_hi = std::clamp(p_hi, p_lo, 1.0);
  // The segment as a cubic polynomial c(p) = c0 + c1 p + c2 p^2 + c3 p^3, from the
  // weights at p = 0 and the derivatives there (exact for a cubic).
  const Vec3 c0 = apply(blend(n, segment, 0.0, 0), q);
  const Vec3 c1 = apply(blend(n, segment, 0.0, 1), q);
  const Vec3 d2 = apply(blend(n, segment, 0.0, 2), q);
  const Vec3 d2b = apply(blend(n, segment, 1.0, 2), q);
  const Vec3 c2 = 0.5 * d2;
  const Vec3 c3 = (d2b - d2) / 6.0;
  auto pos = [&](double p) { return Vec3(c0 + p * (c1 + p * (c2 + p * c3))); };
  auto der = [&](double p) { return Vec3(c1 + p * (2.0 * c2 + p * 3.0 * c3)); };
  auto der2 = [&](double p) { return Vec3(2.0 * c2 + 6.0 * p * c3); };
  // g(p) = d/dp |c(p) - x|^2 / 2
  auto g = [&](double p) { return der(p).dot(pos(p) - x); };
  auto dg = [&](double p) { return der2(p).dot(pos(p) - x) + der(p).squaredNorm(); };

  ClosestPoint best;
  best.segment = segment;
  auto consider = [&](double p) {
    const Vec3 m = pos(p);
    const double d = (m - x).norm();
    if (d < best.distance || best.distance < 0) {
      best.distance = d;
      best.p = p;
      best.point = m;
    }
  };
  best.distance = -1.0;
  consider(p_lo);
  consider(p_hi);

  constexpr int kSamples = 8;
  const double h = (p_hi - p_lo) / kSamples;
  if (h <= 0) return best;
  double a = p_lo, ga = g(a);
  for (int k = 1; k <= kSamples; ++k) {
    const double b = (k == kSamples) ? p_hi : p_lo + k * h;
    const double gb = g(b);
    if (ga < 0 && gb >= 0) {  // a minimum of the distance lies in [a, b]
      double lo = a, hi = b, p = 0.5 * (a + b);
      for (int it = 0; it < 40; ++it) {
        const double gp = g(p);
        if (gp < 0) lo = p; else hi = p;
        const double slope = dg(p);
        double next = (slope > 0) ? p - gp / slope : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - p) < 1e-14) { p = next; break; }
        p = next;
      }
      consider(p);
    }
    a = b;
    ga = gb;
  }
  return best;
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
