// Contact queries: which scope interaction points lie outside the colon lumen, and which
// colon spheres intersect. Two implementations of core's ContactQuery:
//
// - FclContactQuery (the default): FCL's broadphase finds, for every scope segment, the
//   colon segments whose bounds (inflated by the lumen radius and a margin) overlap it,
//   and the colon spheres that overlap each other. Its managers hold bounds fattened by a
//   few millimetres and are updated only when something has moved that far; each query
//   keeps the managers' pairs whose exact bounds overlap (the same pairs). The wall contacts are then found by the
//   contact model's tracking (core/contact_tracking.h: robust near a sigmoid loop), with
//   the broadphase as its candidate search (TrackingCandidates).
// - ScanContactQuery: the paper's method, kept as a reference: every interaction point
//   scans the whole spline for its nearest point (scanWallContacts); every pair of spheres
//   is tested.
//
// Both share the narrowphase (core/spline.h closestParameterOnCubic on per-step cached
// cubics), so where they pick the same colon segment they give bit-identical contacts.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/contact_tracking.h"
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

/// The default fat margin of FclContactQuery's bounds [m].
constexpr double kDefaultFatMargin_m = 0.002;

class FclContactQuery final : public ContactQuery {
 public:
  /// fat_margin_m [m]: how much the managers' colon bounds are fattened, so that they need
  /// updating only when the colon or the scope has moved that far (a Verlet list); the
  /// contacts found are the same whatever the margin (0: updated every query).
  FclContactQuery(const WorldModel& model, const std::string& manager = "dynamic_aabb_tree",
                  double fat_margin_m = kDefaultFatMargin_m);
  ~FclContactQuery() override;
  void findWallContacts(const WorldModel& model, WorldState& state) override;
  void findSelfContacts(const WorldModel& model, WorldState& state) override;
  /// How many times the managers were updated and queried: wall and self.
  long wallRebuilds() const;
  long selfRebuilds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace colosim
