// The brute-force candidate search of the contact tracking (rule 2), for tests: every colon
// segment off the walked stretch, the one of least clearance. The broadphase's search must agree with it.
#pragma once

#include <cmath>
#include <vector>

#include "core/contact_tracking.h"

namespace colosim {

class EverySegment final : public TrackingCandidates {
 public:
  SplineLocation nearestOther(const std::vector<SegmentCubic>& cubics, const ColonModel& colon, const Vec3& x, int,
                              const SplineLocation& local, double local_clearance_m) override {
    SplineLocation other;
    double least = local_clearance_m;
    for (int j = 0; j < static_cast<int>(cubics.size()); ++j)
      if (std::abs(j - local.j) > 1) considerSegmentByClearance(cubics, colon, j, x, other, least);
    return other;
  }
};

}  // namespace colosim
