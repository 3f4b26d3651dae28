// The scope-shape inset of colosim train: the scope's centreline projected coronally (seen
// from the front of the patient), as magnetic endoscope imaging shows it to clinicians.
// Pure data, no GL: the window draws the polyline.
#pragma once

#include <array>
#include <vector>

#include "core/spline.h"

namespace colosim {

/// The patient-frame rectangle an inset shows: x (towards the patient's left) and z
/// (cranial) [m]. The patient's left is on the image's right, as on a radiograph seen
/// from the front; cranial is up.
struct CoronalFrame {
  double x_min_m = -0.2, x_max_m = 0.2;
  double z_min_m = 0.0, z_max_m = 0.4;
};

/// A frame holding every point of `q` (3 x n, e.g. the colon's rest shape) with `margin_m`
/// around it, widened on one axis so that x and z have the same scale in an inset of
/// aspect width / height.
CoronalFrame coronalFrameFor(const Points& q, double aspect, double margin_m = 0.05);

/// The points projected into an inset of width_px x height_px (pixels from its top left,
/// y down): (x, z) of each point mapped linearly from `frame`; points outside the frame
/// land outside the inset (the caller clips).
std::vector<std::array<float, 2>> coronalInset(const std::vector<Vec3>& points_m, const CoronalFrame& frame,
                                               float width_px, float height_px);

}  // namespace colosim
