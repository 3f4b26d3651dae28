#include "trainer/scope_inset.h"

#include <algorithm>

namespace colosim {

CoronalFrame coronalFrameFor(const Points& q, double aspect, double margin_m) {
  CoronalFrame f;
  if (q.cols() == 0 || !(aspect > 0)) return f;
  f.x_min_m = q.row(0).minCoeff() - margin_m, f.x_max_m = q.row(0).maxCoeff() + margin_m;
  f.z_min_m = q.row(2).minCoeff() - margin_m, f.z_max_m = q.row(2).maxCoeff() + margin_m;
  // Equal scales: widen the narrower side about its centre.
  const double w = f.x_max_m - f.x_min_m, h = f.z_max_m - f.z_min_m;
  if (w < aspect * h) {
    const double grow = 0.5 * (aspect * h - w);
    f.x_min_m -= grow, f.x_max_m += grow;
  } else {
    const double grow = 0.5 * (w / aspect - h);
    f.z_min_m -= grow, f.z_max_m += grow;
  }
  return f;
}

std::vector<std::array<float, 2>> coronalInset(const std::vector<Vec3>& points_m, const CoronalFrame& f,
                                               float width_px, float height_px) {
  std::vector<std::array<float, 2>> out;
  out.reserve(points_m.size());
  const double sx = width_px / std::max(1e-9, f.x_max_m - f.x_min_m);
  const double sz = height_px / std::max(1e-9, f.z_max_m - f.z_min_m);
  for (const Vec3& p : points_m)
    out.push_back({static_cast<float>((p.x() - f.x_min_m) * sx), static_cast<float>((f.z_max_m - p.z()) * sz)});
  return out;
}

}  // namespace colosim
