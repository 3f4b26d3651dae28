#include "core/abdominal_pressure.h"

#include <algorithm>
#include <stdexcept>

namespace colosim {

void addRegionSupport(const ColonModel& m, const ColonState& s, const RegionSupport& r,
                      std::vector<SplineLoad>& loads) {
  if (!(r.stiffness_N_per_m2 > 0) && !(r.damping_Ns_per_m2 > 0)) return;
  if (r.anchor_q.cols() == 0) return;
  if (r.anchor_q.cols() != m.n) throw std::invalid_argument("abdominal pressure: the anchor has the wrong number of control points");
  const int first = std::max(0, r.first_segment), last = std::min(m.n - 2, r.last_segment);
  for (int j = first; j <= last; ++j) {
    for (int g = 0; g < Gauss4::kCount; ++g) {
      const Blend b = blend(m.n, j, Gauss4::node[g], 0);
      const double w = Gauss4::weight[g] * m.segment_length_m(j);  // [m]
      const Vec3 u = apply(b, s.q) - apply(b, r.anchor_q);
      const Vec3 v = apply(b, s.v);
      SplineLoad l;
      l.segment = j;
      l.p = Gauss4::node[g];
      l.force_N = -w * (r.stiffness_N_per_m2 * u + r.damping_Ns_per_m2 * v);
      l.stiffness_N_per_m = (w * r.stiffness_N_per_m2) * Mat3::Identity();
      l.damping_Ns_per_m = (w * r.damping_Ns_per_m2) * Mat3::Identity();
      loads.push_back(l);
    }
  }
}

double pressureRamp(double t, double from_s, double to_s, double ramp_s) {
  if (!(t >= from_s) || !(t < to_s)) return 0.0;
  if (!(ramp_s > 0)) return 1.0;
  return std::clamp(std::min(t - from_s, to_s - t) / ramp_s, 0.0, 1.0);
}

}  // namespace colosim
