#include "collision/contact_query.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include <fcl/broadphase/broadphase_SaP.h>
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/broadphase/broadphase_interval_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision_object.h>

namespace colosim {

namespace {

bool selfOverlap(const WorldModel& m, const ColonState& cs, int a, int b, SelfContact* c) {
  if (selfNeighbours(m.contact, m.colon, a, b)) return false;
  const Vec3 d = cs.q.col(b) - cs.q.col(a);
  const double dist = d.norm();
  const double depth = m.colon.radius_m(a) + m.colon.radius_m(b) - dist;
  if (!(depth > 0) || !(dist > 0)) return false;
  c->a = a;
  c->b = b;
  c->normal_W = d / dist;
  c->depth_m = depth;
  return true;
}

// The largest distance any control point has moved from `then` to `now` [m].
double largestMove(const Points& now, const Points& then) {
  double d2 = 0;
  for (Eigen::Index i = 0; i < now.cols(); ++i) d2 = std::max(d2, (now.col(i) - then.col(i)).squaredNorm());
  return std::sqrt(d2);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The paper's scan.

ScanContactQuery::ScanContactQuery(const WorldModel& model) { cubics_.reserve(model.colon.n); }

void ScanContactQuery::findWallContacts(const WorldModel& m, WorldState& s) {
  updateSegmentCubics(s.colon.q, cubics_);
  scanWallContacts(m, cubics_, s);
}

void ScanContactQuery::findSelfContacts(const WorldModel& m, WorldState& s) {
  s.self.clear();
  SelfContact c;
  for (int a = 0; a < m.colon.n; ++a)
    for (int b = a + 1; b < m.colon.n; ++b)
      if (selfOverlap(m, s.colon, a, b, &c)) s.self.push_back(c);
}

// ---------------------------------------------------------------------------------------
// FCL broadphase: the candidate search of core/contact_tracking.h.

std::vector<std::string> fclManagerNames() { return {"dynamic_aabb_tree", "sap", "interval_tree"}; }

namespace {

std::unique_ptr<fcl::BroadPhaseCollisionManagerd> makeManager(const std::string& name) {
  if (name == "dynamic_aabb_tree") {
    auto m = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
    // FCL's update() refits the tree, then takes out and inserts again this many leaves to
    // rebalance it (10 by default). Our objects are chains whose links stay neighbours, so
    // the tree built at registration stays a good one when refitted; the pairs found do not
    // depend on its shape (the queries sort them), so the states are the same bits. FCL
    // still rebuilds it top-down should it grow max_tree_nonbalanced_level beyond log2(n).
    // An update at every query: 87.3 -> 75.3 us for `bench contacts` fcl_query_us
    // (docs/performance.md, session 34).
    m->tree_incremental_balance_pass = 0;
    return m;
  }
  if (name == "sap") return std::make_unique<fcl::SaPCollisionManagerd>();
  if (name == "interval_tree") return std::make_unique<fcl::IntervalTreeCollisionManagerd>();
  throw std::invalid_argument("unknown FCL broadphase manager '" + name +
                              "' (known: dynamic_aabb_tree, sap, interval_tree)");
}

// Objects carry their identity in the user-data pointer: colon segment j as j + 1,
// scope segment k as -(k + 1), colon sphere i as i + 1 (in its own manager).
inline void* tag(long v) { return reinterpret_cast<void*>(static_cast<intptr_t>(v)); }
inline long untag(const fcl::CollisionObjectd* o) {
  return static_cast<long>(reinterpret_cast<intptr_t>(o->getUserData()));
}

struct PairCollector {
  std::vector<std::pair<int, int>>* pairs;
};

bool collectPair(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
  auto* c = static_cast<PairCollector*>(data);
  long a = untag(o1), b = untag(o2);
  if (a < 0) std::swap(a, b);  // (colon segment, scope segment) for the wall query
  c->pairs->emplace_back(static_cast<int>(a - 1), static_cast<int>(b < 0 ? -b - 1 : b - 1));
  return false;  // never stop early
}

}  // namespace

struct FclContactQuery::Impl final : TrackingCandidates {
  explicit Impl(const WorldModel& m) : tracker(m) {}
  SplineLocation nearestOther(const std::vector<SegmentCubic>& cubics, const ColonModel& colon, const Vec3& x,
                              int k, const SplineLocation& local, double local_clearance_m) override;

  ContactTracker tracker;
  std::unique_ptr<fcl::BroadPhaseCollisionManagerd> colon_mgr, scope_mgr, sphere_mgr;
  // The managers hold the colon's boxes and spheres fattened by `fat_m` when they were last
  // updated (colon_objs, sphere_objs); colon_exact holds each step's exact boxes, and the
  // scope's cubes are always exact (the colon's fat covers both sides' motion).
  std::vector<std::shared_ptr<fcl::Boxd>> colon_boxes, colon_exact_boxes;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> colon_objs, colon_exact, scope_objs, sphere_objs;
  double fat_m = 0;
  Points wall_q_built, self_q_built;  // the colon when the managers were last updated [m]
  std::vector<Vec3> scope_p_built;    // the scope segments' centres then [m]
  int inside_built = -1;
  bool wall_built = false, self_built = false;
  // The managers' pairs then: the wall's, and the self query's own (it may run beside the
  // wall query).
  std::vector<std::pair<int, int>> fat_pairs, self_fat_pairs;
  long wall_rebuilds = 0, self_rebuilds = 0;
  std::vector<double> inflate;  // per colon segment: its larger radius and the query margin [m]
  std::vector<Vec3> lo, hi;  // bounds of each colon segment's centreline [m]
  std::vector<Vec3> mid;     // centre of each segment's Bezier hull ...
  std::vector<double> rho;   // ... and the radius of a ball around it holding the segment [m]
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> first;    // per scope segment: start of its candidates in `pairs` (K + 1)
  std::vector<int> fill;
  std::vector<std::pair<int, int>> grouped;
  std::vector<std::pair<double, int>> order;
};

// Other colon segments near x (broadphase candidates of scope segment k off the walked
// stretch), by a lower bound of their clearance (a lower bound of the distance less the
// segment's largest radius), skipping those that cannot beat the best so far.
SplineLocation FclContactQuery::Impl::nearestOther(const std::vector<SegmentCubic>& cubics, const ColonModel& colon,
                                                   const Vec3& x, int k, const SplineLocation& local,
                                                   double local_clearance_m) {
  order.clear();
  for (int c = first[k]; c < first[k + 1]; ++c) {
    const int j = pairs[c].first;
    if (std::abs(j - local.j) <= 1) continue;
    const double r_max = std::max(colon.radius_m(j), colon.radius_m(j + 1));
    // Two lower bounds of the distance to the segment: its box (squared, no root unless
    // it can pass) and its ball.
    const double reach = local_clearance_m + r_max;  // farther than this cannot beat the walk
    if (!(reach > 0)) continue;
    const double box2 = (lo[j] - x).cwiseMax(x - hi[j]).cwiseMax(0.0).squaredNorm();
    if (!(box2 < reach * reach)) continue;
    const double bound = std::max(std::sqrt(box2), (x - mid[j]).norm() - rho[j]) - r_max;
    if (bound < local_clearance_m) order.emplace_back(bound, j);
  }
  std::sort(order.begin(), order.end());
  SplineLocation other;
  double best = local_clearance_m;
  for (const auto& [bound, j] : order) {
    if (bound >= best) break;
    considerSegmentByClearance(cubics, colon, j, x, other, best);
  }
  return other;
}

FclContactQuery::FclContactQuery(const WorldModel& m, const std::string& manager, double fat_margin_m)
    : impl_(new Impl(m)) {
  Impl& I = *impl_;
  I.colon_mgr = makeManager(manager);
  I.scope_mgr = makeManager(manager);
  I.sphere_mgr = makeManager(manager);
  const int nseg = m.colon.n - 1;
  I.lo.resize(nseg);
  I.hi.resize(nseg);
  I.mid.resize(nseg);
  I.rho.resize(nseg);
  I.inflate.resize(nseg);
  for (int j = 0; j < nseg; ++j) {
    I.inflate[j] = std::max(m.colon.radius_m(j), m.colon.radius_m(j + 1)) + m.contact.query_margin_m;
    auto box = std::make_shared<fcl::Boxd>(1.0, 1.0, 1.0);
    auto obj = std::make_unique<fcl::CollisionObjectd>(box);
    obj->setUserData(tag(j + 1));
    I.colon_boxes.push_back(box);
    I.colon_objs.push_back(std::move(obj));
    auto exact_box = std::make_shared<fcl::Boxd>(1.0, 1.0, 1.0);
    I.colon_exact.push_back(std::make_unique<fcl::CollisionObjectd>(exact_box));
    I.colon_exact_boxes.push_back(exact_box);
  }
  // A scope segment and its interaction points fit in a cube of half-side sqrt((h/2)^2 + r^2).
  const double half = std::sqrt(0.25 * m.scope.h_m * m.scope.h_m + m.scope.radius_m * m.scope.radius_m);
  auto scope_box = std::make_shared<fcl::Boxd>(2 * half, 2 * half, 2 * half);
  for (int k = 0; k < m.scope.segment_count; ++k) {
    auto obj = std::make_unique<fcl::CollisionObjectd>(scope_box);
    obj->setUserData(tag(-(k + 1)));
    I.scope_objs.push_back(std::move(obj));
  }
  I.fat_m = fat_margin_m > 0 ? fat_margin_m : 0.0;
  for (int i = 0; i < m.colon.n; ++i) {
    const double r = m.colon.radius_m(i) + 0.5 * I.fat_m;
    auto obj = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Sphered>(r));
    obj->setUserData(tag(i + 1));
    I.sphere_objs.push_back(std::move(obj));
  }
  // Register at the rest pose; queries move the objects and update the managers.
  for (int j = 0; j < nseg; ++j) {
    I.colon_objs[j]->setTranslation(m.colon.q_rest.col(j));
    I.colon_objs[j]->computeAABB();
    I.colon_mgr->registerObject(I.colon_objs[j].get());
  }
  for (int k = 0; k < m.scope.segment_count; ++k) {
    I.scope_objs[k]->setTranslation(Vec3(1e3 + k, 1e3, 1e3));
    I.scope_objs[k]->computeAABB();
    I.scope_mgr->registerObject(I.scope_objs[k].get());
  }
  for (int i = 0; i < m.colon.n; ++i) {
    I.sphere_objs[i]->setTranslation(m.colon.q_rest.col(i));
    I.sphere_objs[i]->computeAABB();
    I.sphere_mgr->registerObject(I.sphere_objs[i].get());
  }
  I.colon_mgr->setup();
  I.scope_mgr->setup();
  I.sphere_mgr->setup();
  I.pairs.reserve(64 * m.scope.segment_count);
  I.fat_pairs.reserve(128 * m.scope.segment_count);
  I.self_fat_pairs.reserve(32 * m.colon.n);
  I.scope_p_built.resize(m.scope.segment_count);
  I.first.resize(m.scope.segment_count + 1);
  I.fill.reserve(std::max(nseg, m.scope.segment_count) + 1);
}

FclContactQuery::~FclContactQuery() = default;

void FclContactQuery::findWallContacts(const WorldModel& m, WorldState& s) {
  Impl& I = *impl_;
  const ColonModel& colon = m.colon;
  const int nseg = colon.n - 1;
  I.tracker.updateCubics(s.colon);
  const std::vector<SegmentCubic>& cubics = I.tracker.cubics();

  // Broadphase: colon segments (centreline bounds inflated by the lumen radius and the
  // margin) against scope segments (their bounding cubes; those outside are parked far away).
  for (int j = 0; j < nseg; ++j) {
    // The segment lies in the convex hull of its Bezier control points: a box and a ball.
    const SegmentCubic& c = cubics[j];
    const Vec3 b0 = c.c0, b3 = c.at(1.0), b1 = b0 + c.c1 / 3.0;
    const Vec3 b2 = b3 - (c.c1 + 2.0 * c.c2 + 3.0 * c.c3) / 3.0;
    I.lo[j] = b0.cwiseMin(b1).cwiseMin(b2).cwiseMin(b3);
    I.hi[j] = b0.cwiseMax(b1).cwiseMax(b2).cwiseMax(b3);
    I.mid[j] = 0.25 * (b0 + b1 + b2 + b3);
    I.rho[j] = std::max({(b0 - I.mid[j]).norm(), (b1 - I.mid[j]).norm(), (b2 - I.mid[j]).norm(),
                         (b3 - I.mid[j]).norm()});
    if (!(I.fat_m > 0)) continue;  // the managers' boxes are the exact ones
    const Vec3 lo = I.lo[j].array() - I.inflate[j], hi = I.hi[j].array() + I.inflate[j];
    I.colon_exact_boxes[j]->side = hi - lo;
    I.colon_exact_boxes[j]->computeLocalAABB();
    I.colon_exact[j]->setTranslation(0.5 * (lo + hi));
    I.colon_exact[j]->computeAABB();
  }
  for (int k = 0; k < m.scope.segment_count; ++k) {
    I.scope_objs[k]->setTranslation(k < s.scope.inside ? s.scope.p_W[k] : Vec3(1e3 + k, 1e3, 1e3));
    I.scope_objs[k]->computeAABB();
  }
  // The managers' pairs, of the bounds fattened by fat_m when they were last updated, hold
  // every pair of exact bounds overlapping now while 2 D_colon + D_scope <= fat_m, with D
  // the largest move of a control point or a scope segment's centre since: a colon box
  // follows its Bezier points, each a combination of control points whose weights' sizes
  // sum to at most 2. Past that (or when segments enter or leave), the managers are updated.
  bool rebuild = !I.wall_built || s.scope.inside != I.inside_built || !(I.fat_m > 0);
  if (!rebuild) {
    double dp2 = 0;
    for (int k = 0; k < s.scope.inside; ++k) dp2 = std::max(dp2, (s.scope.p_W[k] - I.scope_p_built[k]).squaredNorm());
    // 10 % for the bounds' rounding.
    rebuild = !(2.0 * largestMove(s.colon.q, I.wall_q_built) + std::sqrt(dp2) <= 0.9 * I.fat_m);
  }
  if (rebuild) {
    for (int j = 0; j < nseg; ++j) {
      const Vec3 lo = (I.lo[j].array() - I.inflate[j]) - I.fat_m, hi = (I.hi[j].array() + I.inflate[j]) + I.fat_m;
      I.colon_boxes[j]->side = hi - lo;
      I.colon_boxes[j]->computeLocalAABB();
      I.colon_objs[j]->setTranslation(0.5 * (lo + hi));
      I.colon_objs[j]->computeAABB();
    }
    I.colon_mgr->update();
    I.scope_mgr->update();
    I.fat_pairs.clear();
    PairCollector collector{&I.fat_pairs};
    I.colon_mgr->collide(I.scope_mgr.get(), &collector, collectPair);
    I.wall_q_built = s.colon.q;
    for (int k = 0; k < s.scope.inside; ++k) I.scope_p_built[k] = s.scope.p_W[k];
    I.inside_built = s.scope.inside;
    I.wall_built = true;
    ++I.wall_rebuilds;
  }
  // This step's candidates: the pairs whose exact bounds overlap, by FCL's own test, so
  // the same pairs as a broadphase of the exact bounds finds.
  I.pairs.clear();
  if (!(I.fat_m > 0)) {
    I.pairs.assign(I.fat_pairs.begin(), I.fat_pairs.end());
  } else {
    for (const auto& pr : I.fat_pairs)
      if (I.colon_exact[pr.first]->getAABB().overlap(I.scope_objs[pr.second]->getAABB())) I.pairs.push_back(pr);
  }
  // Candidates grouped by scope segment, each group in ascending colon segment order: the
  // result does not depend on the tree's traversal order. Two stable counting sorts (by
  // colon segment, then by scope segment) give that order without comparisons (the sort
  // of each group took a tenth of the step).
  const int K = m.scope.segment_count;
  I.grouped.resize(I.pairs.size());
  I.fill.assign(nseg + 1, 0);
  for (const auto& pr : I.pairs) ++I.fill[pr.first + 1];
  for (int j = 0; j < nseg; ++j) I.fill[j + 1] += I.fill[j];
  for (const auto& pr : I.pairs) I.grouped[I.fill[pr.first]++] = pr;
  std::fill(I.first.begin(), I.first.end(), 0);
  for (const auto& pr : I.grouped) ++I.first[pr.second + 1];
  for (int k = 0; k < K; ++k) I.first[k + 1] += I.first[k];
  I.fill.assign(I.first.begin(), I.first.end() - 1);
  for (const auto& pr : I.grouped) I.pairs[I.fill[pr.second]++] = pr;

  // Narrowphase: the contact model's tracking, with the broadphase's candidates.
  I.tracker.trackWallContacts(m, s, I);
}

void FclContactQuery::findSelfContacts(const WorldModel& m, WorldState& s) {
  Impl& I = *impl_;
  // The manager's spheres are fattened by fat_m / 2 each: its pairs of when it was last
  // updated hold every pair overlapping now while no control point has moved more than
  // fat_m / 2 since. The exact test (selfOverlap) then decides, so the contacts are those
  // of the exact spheres whatever the fat.
  bool rebuild = !I.self_built || !(I.fat_m > 0);
  if (!rebuild) rebuild = !(2.0 * largestMove(s.colon.q, I.self_q_built) <= 0.9 * I.fat_m);
  if (rebuild) {
    for (int i = 0; i < m.colon.n; ++i) {
      I.sphere_objs[i]->setTranslation(s.colon.q.col(i));
      I.sphere_objs[i]->computeAABB();
    }
    I.sphere_mgr->update();
    I.self_fat_pairs.clear();
    PairCollector collector{&I.self_fat_pairs};
    I.sphere_mgr->collide(&collector, collectPair);
    for (auto& pr : I.self_fat_pairs)
      if (pr.first > pr.second) std::swap(pr.first, pr.second);
    std::sort(I.self_fat_pairs.begin(), I.self_fat_pairs.end());
    I.self_q_built = s.colon.q;
    I.self_built = true;
    ++I.self_rebuilds;
  }
  s.self.clear();
  SelfContact c;
  for (const auto& [a, b] : I.self_fat_pairs)
    if (selfOverlap(m, s.colon, a, b, &c)) s.self.push_back(c);
}

long FclContactQuery::wallRebuilds() const { return impl_->wall_rebuilds; }
long FclContactQuery::selfRebuilds() const { return impl_->self_rebuilds; }

std::unique_ptr<ContactQuery> makeContactQuery(const WorldModel& model, const std::string& mode) {
  if (mode == "scan") return std::make_unique<ScanContactQuery>(model);
  if (mode == "fcl") return std::make_unique<FclContactQuery>(model);
  if (mode.rfind("fcl:", 0) == 0) return std::make_unique<FclContactQuery>(model, mode.substr(4));
  throw std::invalid_argument("unknown contact query mode '" + mode + "' (known: fcl, fcl:MANAGER, scan)");
}

}  // namespace colosim
