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

}  // namespace colosim
