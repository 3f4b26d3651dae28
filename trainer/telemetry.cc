#include "trainer/telemetry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <complex>

#include <Eigen/Geometry>

namespace colosim {

double netTurns(const std::vector<Vec3>& polyline_m, const Vec3& normal) {
  const Vec3 n = normal.normalized();
  double total_rad = 0.0;
  Vec3 prev = Vec3::Zero();
  bool have_prev = false;
  for (size_t i = 1; i < polyline_m.size(); ++i) {
    Vec3 d = polyline_m[i] - polyline_m[i - 1];
    d -= n * n.dot(d);  // projection on the plane
    if (d.norm() < 1e-9) continue;
    if (have_prev) total_rad += std::atan2(n.dot(prev.cross(d)), prev.dot(d));
    prev = d;
    have_prev = true;
  }
  return total_rad / (2.0 * 3.14159265358979323846);
}

double crossingLoopTurns(const std::vector<Vec3>& polyline_m, const Vec3& normal) {
  const Vec3 n = normal.normalized();
  // A right-handed basis (u, v, n) of the plane: angles in it are anticlockwise seen from n.
  const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  thread_local std::vector<Eigen::Vector2d> p;  // measured after every step: no allocation once grown
  p.clear();
  for (const Vec3& x : polyline_m) {
    const Eigen::Vector2d q(u.dot(x), v.dot(x));
    if (p.empty() || (q - p.back()).norm() >= 1e-9) p.push_back(q);  // drop null segments
  }
  const int segments = static_cast<int>(p.size()) - 1;
  auto cross2 = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  auto turn = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return std::atan2(cross2(a, b), a.dot(b)); };
  // The turn at each vertex, computed the first time a loop runs through it (NaN until
  // then): loops found at several crossings share most of their vertices.
  thread_local std::vector<double> vertex_turn;
  vertex_turn.assign(std::max(segments - 1, 0), std::numeric_limits<double>::quiet_NaN());
  auto turnAt = [&](int i) {
    double& v = vertex_turn[i];
    if (std::isnan(v)) v = turn(p[i + 1] - p[i], p[i + 2] - p[i + 1]);
    return v;
  };
  double best = 0.0;
  for (int a = 0; a < segments; ++a) {
    const Eigen::Vector2d da = p[a + 1] - p[a];
    for (int b = a + 2; b < segments; ++b) {
      const Eigen::Vector2d db = p[b + 1] - p[b];
      const double den = cross2(da, db);
      if (std::abs(den) < 1e-18) continue;  // parallel
      // p[a] + s da = p[b] + t db, s and t in [0, 1) (half-open: a crossing at a shared
      // corner counts once).
      const Eigen::Vector2d w = p[b] - p[a];
      const double s = cross2(w, db) / den, t = cross2(w, da) / den;
      if (s < 0 || s >= 1 || t < 0 || t >= 1) continue;
      // The loop's edges run along segments a, a+1, ..., b, then close from b back to a at X.
      double total_rad = turn(db, da);
      for (int i = a; i < b; ++i) total_rad += turnAt(i);
      const double turns = std::round(total_rad / (2.0 * 3.14159265358979323846));
      if (std::abs(turns) > std::abs(best)) best = turns;
    }
  }
  return best;
}

double closedWrithe(const std::vector<Vec3>& polyline_m) {
  // Drop null segments, then close the polygon with the chord from the last point back to
  // the first (no chord when the line already ends where it starts).
  std::vector<Vec3> p;
  p.reserve(polyline_m.size() + 1);
  for (const Vec3& x : polyline_m)
    if (p.empty() || (x - p.back()).norm() >= 1e-9) p.push_back(x);
  if (p.size() > 1 && (p.back() - p.front()).norm() < 1e-9) p.pop_back();
  const int m = static_cast<int>(p.size());  // edges of the closed polygon: i -> i + 1 (mod m)
  if (m < 4) return 0.0;                     // a triangle is planar
  // The unit vectors between every two vertices (each pair of edges uses four of them).
  thread_local std::vector<Vec3> u;
  u.resize(static_cast<size_t>(m) * m);
  for (int i = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j) {
      const Vec3 d = p[j] - p[i];
      const double l = d.norm();
      u[i * m + j] = l > 0 ? Vec3(d / l) : Vec3::Zero();
      u[j * m + i] = -u[i * m + j];
    }
  // Solid angle of the spherical triangle of unit vectors a, b, c, signed by their
  // orientation (Van Oosterom & Strackee 1983): omega / 2 = arg(1 + a.b + b.c + c.a + i [a b c]).
  auto triangle = [](const Vec3& a, const Vec3& b, const Vec3& c) {
    return std::complex<double>(1.0 + a.dot(b) + b.dot(c) + c.dot(a), a.dot(b.cross(c)));
  };
  double sum_sr = 0.0;  // sum of signed solid angles over unordered pairs of edges [sr]
  for (int i = 0; i < m; ++i) {
    const int i2 = (i + 1) % m;
    const Vec3& p1 = p[i];
    const Vec3& p2 = p[i2];
    for (int j = i + 2; j < m; ++j) {
      if (i == 0 && j == m - 1) continue;  // the closing edge is adjacent to edge 0
      const int j2 = (j + 1) % m;
      // The solid angle under which edge j is seen from all points of edge i, over 4 pi, is
      // the pair's contribution to the Gauss integral (Klenin & Langowski 2000, method 1a):
      // the quadrilateral of directions r13, r14, r24, r23, here as two triangles.
      const Vec3& a = u[i * m + j];    // r13
      const Vec3& b = u[i * m + j2];   // r14
      const Vec3& c = u[i2 * m + j2];  // r24
      const Vec3& d = u[i2 * m + j];   // r23
      // The two halves' arguments add by multiplying (one arctangent): the quadrilateral's
      // solid angle is at most 2 pi, so its half stays within the argument's range.
      const std::complex<double> z1 = triangle(a, b, c), z2 = triangle(a, c, d);
      const double re = z1.real() * z2.real() - z1.imag() * z2.imag();
      const double im = z1.real() * z2.imag() + z1.imag() * z2.real();
      const double omega = std::abs(2.0 * std::atan2(im, re));
      const double orient = (p[j2] - p[j]).cross(p2 - p1).dot(p[j] - p1);
      if (orient > 0) sum_sr += omega;
      else if (orient < 0) sum_sr -= omega;
    }
  }
  // Wr = (1 / 4 pi) sum over ordered pairs = (1 / 2 pi) sum over unordered pairs.
  return sum_sr / (2.0 * 3.14159265358979323846);
}

double writheClosedFarAway(const std::vector<Vec3>& polyline_m, const Vec3& out_start, const Vec3& out_end) {
  if (polyline_m.size() < 2) return 0.0;
  double extent_m = 0.0;
  for (const Vec3& x : polyline_m) extent_m = std::max(extent_m, (x - polyline_m.front()).norm());
  // Far enough that the rays' far ends and the segment joining them contribute less than
  // 1e-6 turn (their solid angles fall as extent / distance).
  const double far_m = 1e6 * std::max(extent_m, 1e-3);
  std::vector<Vec3> closed;
  closed.reserve(polyline_m.size() + 2);
  closed.push_back(polyline_m.front() + far_m * out_start.normalized());
  closed.insert(closed.end(), polyline_m.begin(), polyline_m.end());
  closed.push_back(polyline_m.back() + far_m * out_end.normalized());
  return closedWrithe(closed);
}

void regionLengthRatios(const ColonModel& colon, const Points& q, std::vector<double>& ratios) {
  const size_t regions = colon.region_names.size();
  std::vector<double> present_m(regions, 0.0), rest_m(regions, 0.0);
  for (int j = 0; j + 1 < colon.n; ++j) {
    const int r = colon.segment_region[j];
    present_m[r] += (q.col(j + 1) - q.col(j)).norm();
    rest_m[r] += colon.rest_length_m(j);
  }
  ratios.assign(regions, 0.0);
  for (size_t r = 0; r < regions; ++r) ratios[r] = rest_m[r] > 0 ? present_m[r] / rest_m[r] : 1.0;
}

double colonStretch(const std::vector<double>& region_length_ratios) {
  double stretch = 0.0;
  for (double r : region_length_ratios) stretch = std::max(stretch, r - 1.0);
  return stretch;
}

}  // namespace colosim
