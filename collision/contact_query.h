// Contact queries: which scope interaction points lie outside the colon lumen, and which
// colon spheres intersect. Two implementations of core's ContactQuery:
//
// - FclContactQuery (the default): FCL's broadphase finds, for every scope segment, the
//   colon segments whose bounds (inflated by the lumen radius and a margin) overlap it,
//   and the colon spheres that overlap each other; the exact nearest spline point is then
//   found on those candidates only. It is robust near a sigmoid loop: each interaction
//   point keeps the spline location where it last found the wall, and a candidate on a
//   far part of the colon (in arclength) does not take over from the tracked part while
//   the point is still within the tracked lumen's reach.
// - ScanContactQuery: the paper's method, kept as a reference: every interaction point
//   scans the whole spline for its nearest point; every pair of spheres is tested.
//
// Both share the narrowphase (core/spline.h closestParameterOnCubic on per-step cached
// cubics), so where they pick the same colon segment they give bit-identical contacts.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/world.h"

namespace colosim {

/// FCL broadphase managers we can use: "dynamic_aabb_tree" (default), "sap", "interval_tree".
std::vector<std::string> fclManagerNames();

/// A query of the given mode: "fcl" (with manager "dynamic_aabb_tree" unless given
/// "fcl:sap" etc.) or "scan". Throws std::invalid_argument for an unknown mode.
std::unique_ptr<ContactQuery> makeContactQuery(const WorldModel& model, const std::string& mode);

/// The paper's scan (reference mode).
class ScanContactQuery final : public ContactQuery {
 public:
  explicit ScanContactQuery(const WorldModel& model);
  void findWallContacts(const WorldModel& model, WorldState& state) override;
  void findSelfContacts(const WorldModel& model, WorldState& state) override;

 private:
  std::vector<SegmentCubic> cubics_;
};

class FclContactQuery final : public ContactQuery {
 public:
  FclContactQuery(const WorldModel& model, const std::string& manager = "dynamic_aabb_tree");
  ~FclContactQuery() override;
  void findWallContacts(const WorldModel& model, WorldState& state) override;
  void findSelfContacts(const WorldModel& model, WorldState& state) override;

  /// Nearest spline location to x found by walking from segment `start` (-1: none) and
  /// checking the broadphase candidates pairs[c0, c1) for other parts of the colon.
  struct Nearest {
    int j = -1;      ///< colon segment, -1 when none
    double p = 0;    ///< parameter on it
    double d = 1e300;  ///< distance [m]
  };

 private:
  Nearest nearestRobust(const WorldModel& model, const Vec3& x, int start, int c0, int c1);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace colosim
