// Small colons written inline for the contact-tracking and lumen-check tests.
#pragma once

#include <cmath>
#include <memory>

#include "core/tension_law.h"
#include "core/world.h"

namespace colosim {

/// A world whose colon has control points q and a constant lumen radius [m], default scope and contacts.
inline WorldModel smallWorld(const Points& q, double radius_m) {
  ColonModel colon = buildColonModelFromPoints(q, Eigen::VectorXd::Constant(q.cols(), radius_m), 0.4, 1000, 20,
                                               Vec3::Zero(), std::make_shared<VoigtLaw>(28.9, 0.05));
  return makeWorldModel(std::move(colon), ScopeParams(), ContactParams());
}

/// Straight down -z from the anus at the origin, 1.5 cm between control points.
inline Points straightDown(double length_m) {
  const int n = static_cast<int>(std::lround(length_m / 0.015)) + 1;
  Points q(3, n);
  for (int i = 0; i < n; ++i) q.col(i) = Vec3(0, 0, -0.015 * i);
  return q;
}

}  // namespace colosim
