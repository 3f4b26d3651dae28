#include "trainer/telemetry.h"

#include <cmath>

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
  std::vector<Eigen::Vector2d> p;
  p.reserve(polyline_m.size());
  for (const Vec3& x : polyline_m) {
    const Eigen::Vector2d q(u.dot(x), v.dot(x));
    if (p.empty() || (q - p.back()).norm() >= 1e-9) p.push_back(q);  // drop null segments
  }
  const int segments = static_cast<int>(p.size()) - 1;
  auto cross2 = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  auto turn = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return std::atan2(cross2(a, b), a.dot(b)); };
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
      for (int i = a; i < b; ++i) total_rad += turn(p[i + 1] - p[i], p[i + 2] - p[i + 1]);
      const double turns = std::round(total_rad / (2.0 * 3.14159265358979323846));
      if (std::abs(turns) > std::abs(best)) best = turns;
    }
  }
  return best;
}

}  // namespace colosim
