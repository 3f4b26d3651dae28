#include "core/colon_threading.h"

#include <algorithm>
#include <cmath>

namespace colosim {

void findThreadingContacts(const WorldModel& m, const WorldState& s, std::vector<WallContact>& out) {
  const int slices = m.scope.params.slices_per_segment;
  const int n = m.colon.n;
  const double behind_m = m.contact.wall_thickness_m - m.scope.radius_m;  // added to r_i [m]
  // The chain of slices from the anus to the tip, as the tracking walks it; a slice
  // without a track breaks it.
  int prev_k = -1, prev_sl = 0;
  for (int k = s.scope.inside - 1; k >= 0; --k) {
    for (int sl = 0; sl < slices; ++sl) {
      const WallTrack& b = s.slice_track[static_cast<size_t>(k) * slices + sl];
      if (b.colon_segment < 0) {
        prev_k = -1;
        continue;
      }
      if (prev_k >= 0) {
        const WallTrack& a = s.slice_track[static_cast<size_t>(prev_k) * slices + prev_sl];
        const double ta = a.colon_segment + a.p, tb = b.colon_segment + b.p;  // places along the colon
        const int first = std::max(1, static_cast<int>(std::floor(std::min(ta, tb))) + 1);
        const int last = std::min(n - 2, static_cast<int>(std::ceil(std::max(ta, tb))) - 1);
        if (first <= last) {
          const Vec3 ca = sliceCentre(m.scope, s.scope, prev_k, prev_sl);
          const Vec3 ab = sliceCentre(m.scope, s.scope, k, sl) - ca;
          const double len2 = ab.squaredNorm();
          for (int i = first; i <= last; ++i) {
            const Vec3 q = s.colon.q.col(i);
            const double u = len2 > 0 ? std::clamp((q - ca).dot(ab) / len2, 0.0, 1.0) : 0.0;
            const Vec3 y = ca + u * ab;
            const Vec3 d = y - q;
            const double e = d.norm();
            const double depth = e - (m.colon.radius_m(i) + behind_m);
            if (!(depth > 0)) continue;
            WallContact c;
            c.scope_segment = u < 0.5 ? prev_k : k;
            c.point = 0;
            c.p_W_point = y;
            c.colon_segment = i;
            c.p = 0.0;
            c.p_W_centre = q;
            c.normal_W = d / e;
            c.depth_m = depth;
            out.push_back(c);
          }
        }
      }
      prev_k = k;
      prev_sl = sl;
    }
  }
}

void applyThreadingContacts(const WorldModel& m, WorldState& s) {
  s.threading.clear();
  if (!(m.contact.threading_stiffness_N_per_m > 0)) return;
  findThreadingContacts(m, s, s.threading);
  if (s.threading.empty()) return;
  // Eq. 7 with the threading stiffness from the depth beyond the wall's thickness: no
  // second backing.
  ContactParams p = m.contact;
  p.wall_stiffness_N_per_m = m.contact.threading_stiffness_N_per_m;
  p.wall_backing_stiffness_N_per_m = 0;
  ContactLimitReport limit;
  const double f = applyWallContacts(p, m.colon, s.colon, m.scope, s.scope, s.threading, s.colon.loads,
                                     s.scope.loads, &limit);
  s.max_wall_force_N = std::max(s.max_wall_force_N, f);
  s.contact_limit.limited += limit.limited;
  s.contact_limit.non_finite += limit.non_finite;
  s.contact_limit.asked_N = std::max(s.contact_limit.asked_N, limit.asked_N);
}

}  // namespace colosim
