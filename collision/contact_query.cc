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

constexpr double kInf = std::numeric_limits<double>::infinity();

using Nearest = FclContactQuery::Nearest;

void updateCubics(const ColonModel& colon, const ColonState& cs, std::vector<SegmentCubic>& cubics) {
  cubics.resize(colon.n - 1);
  for (int j = 0; j + 1 < colon.n; ++j) cubics[j] = segmentCubic(cs.q, j);
}

inline void consider(const std::vector<SegmentCubic>& cubics, int j, const Vec3& x, Nearest& best) {
  double d;
  const double p = closestParameterOnCubic(cubics[j], x, 0.0, 1.0, &d);
  if (d < best.d) best = {j, p, d};
}

// Appends a contact when the interaction point lies outside the lumen at its location.
inline void recordIfOutside(const WorldModel& m, const std::vector<SegmentCubic>& cubics, int k, int i,
                            const Vec3& x, const Nearest& at, std::vector<WallContact>& out) {
  const double radius = m.colon.radiusAt(at.j, at.p);
  if (!(at.d > radius)) return;
  WallContact c;
  c.scope_segment = k;
  c.point = i;
  c.p_W_point = x;
  c.colon_segment = at.j;
  c.p = at.p;
  c.p_W_centre = cubics[at.j].at(at.p);
  c.normal_W = (x - c.p_W_centre) / at.d;
  c.depth_m = at.d - radius;
  out.push_back(c);
}

// The local minimum of the distance from x along the spline, walking from segment `start`
// (-1: none found): while the minimum sits at a segment end, try the next segment.
Nearest walkToNearest(const std::vector<SegmentCubic>& cubics, const Vec3& x, int start) {
  Nearest local;
  if (start < 0) return local;
  const int nseg = static_cast<int>(cubics.size());
  int j = std::min(start, nseg - 1);
  consider(cubics, j, x, local);
  int lo = j, hi = j;
  for (int it = 0; it < nseg; ++it) {
    if (local.p <= 0.0 && lo > 0) {
      const Nearest before = local;
      consider(cubics, --lo, x, local);
      if (local.j == before.j) break;
    } else if (local.p >= 1.0 && hi < nseg - 1) {
      const Nearest before = local;
      consider(cubics, ++hi, x, local);
      if (local.j == before.j) break;
    } else {
      break;
    }
  }
  return local;
}

void resetOutsideTracks(const WorldModel& m, WorldState& s) {
  const size_t P = m.scope.interaction_points_S.size();
  for (size_t t = static_cast<size_t>(s.scope.inside) * P; t < s.track.size(); ++t) s.track[t] = WallTrack();
}

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

}  // namespace

// ---------------------------------------------------------------------------------------
// The paper's scan.

ScanContactQuery::ScanContactQuery(const WorldModel& model) { cubics_.reserve(model.colon.n); }

void ScanContactQuery::findWallContacts(const WorldModel& m, WorldState& s) {
  updateCubics(m.colon, s.colon, cubics_);
  s.wall.clear();
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  for (int k = 0; k < s.scope.inside; ++k) {
    for (int i = 0; i < P; ++i) {
      const Vec3 x = interactionPoint(m.scope, s.scope, k, i);
      Nearest best;
      for (int j = 0; j + 1 < m.colon.n; ++j) consider(cubics_, j, x, best);
      s.track[k * P + i] = {best.j, best.p};
      recordIfOutside(m, cubics_, k, i, x, best, s.wall);
    }
  }
  resetOutsideTracks(m, s);
}

void ScanContactQuery::findSelfContacts(const WorldModel& m, WorldState& s) {
  s.self.clear();
  SelfContact c;
  for (int a = 0; a < m.colon.n; ++a)
    for (int b = a + 1; b < m.colon.n; ++b)
      if (selfOverlap(m, s.colon, a, b, &c)) s.self.push_back(c);
}

// ---------------------------------------------------------------------------------------
// FCL broadphase with tracked, robust narrowphase.

std::vector<std::string> fclManagerNames() { return {"dynamic_aabb_tree", "sap", "interval_tree"}; }

namespace {

std::unique_ptr<fcl::BroadPhaseCollisionManagerd> makeManager(const std::string& name) {
  if (name == "dynamic_aabb_tree") return std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
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

struct FclContactQuery::Impl {
  std::unique_ptr<fcl::BroadPhaseCollisionManagerd> colon_mgr, scope_mgr, sphere_mgr;
  std::vector<std::shared_ptr<fcl::Boxd>> colon_boxes;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> colon_objs, scope_objs, sphere_objs;
  std::vector<SegmentCubic> cubics;
  std::vector<Vec3> lo, hi;  // bounds of each colon segment's centreline [m]
  std::vector<Vec3> mid;     // centre of each segment's Bezier hull ...
  std::vector<double> rho;   // ... and the radius of a ball around it holding the segment [m]
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> first;    // per scope segment: start of its candidates in `pairs` (K + 1)
  std::vector<int> fill;
  std::vector<std::pair<int, int>> grouped;
  std::vector<std::pair<double, int>> order;
  std::vector<Nearest> axes;  // per scope segment and slice: the slice centre's spline location
  std::vector<char> moved;    // ... and whether it was taken back to the scope's path
};

FclContactQuery::FclContactQuery(const WorldModel& m, const std::string& manager) : impl_(new Impl) {
  Impl& I = *impl_;
  I.colon_mgr = makeManager(manager);
  I.scope_mgr = makeManager(manager);
  I.sphere_mgr = makeManager(manager);
  const int nseg = m.colon.n - 1;
  const ColonState rest = makeColonState(m.colon, 0);
  updateCubics(m.colon, rest, I.cubics);
  I.lo.resize(nseg);
  I.hi.resize(nseg);
  I.mid.resize(nseg);
  I.rho.resize(nseg);
  for (int j = 0; j < nseg; ++j) {
    auto box = std::make_shared<fcl::Boxd>(1.0, 1.0, 1.0);
    auto obj = std::make_unique<fcl::CollisionObjectd>(box);
    obj->setUserData(tag(j + 1));
    I.colon_boxes.push_back(box);
    I.colon_objs.push_back(std::move(obj));
  }
  // A scope segment and its interaction points fit in a cube of half-side sqrt((h/2)^2 + r^2).
  const double half = std::sqrt(0.25 * m.scope.h_m * m.scope.h_m + m.scope.radius_m * m.scope.radius_m);
  auto scope_box = std::make_shared<fcl::Boxd>(2 * half, 2 * half, 2 * half);
  for (int k = 0; k < m.scope.segment_count; ++k) {
    auto obj = std::make_unique<fcl::CollisionObjectd>(scope_box);
    obj->setUserData(tag(-(k + 1)));
    I.scope_objs.push_back(std::move(obj));
  }
  for (int i = 0; i < m.colon.n; ++i) {
    auto obj = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Sphered>(m.colon.radius_m(i)));
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
  I.first.resize(m.scope.segment_count + 1);
}

FclContactQuery::~FclContactQuery() = default;

void FclContactQuery::findWallContacts(const WorldModel& m, WorldState& s) {
  Impl& I = *impl_;
  const ColonModel& colon = m.colon;
  const int nseg = colon.n - 1;
  updateCubics(colon, s.colon, I.cubics);

  // Broadphase: colon segments (centreline bounds inflated by the lumen radius and the
  // margin) against scope segments (their bounding cubes; those outside are parked far away).
  for (int j = 0; j < nseg; ++j) {
    // The segment lies in the convex hull of its Bezier control points: a box and a ball.
    const SegmentCubic& c = I.cubics[j];
    const Vec3 b0 = c.c0, b3 = c.at(1.0), b1 = b0 + c.c1 / 3.0;
    const Vec3 b2 = b3 - (c.c1 + 2.0 * c.c2 + 3.0 * c.c3) / 3.0;
    I.lo[j] = b0.cwiseMin(b1).cwiseMin(b2).cwiseMin(b3);
    I.hi[j] = b0.cwiseMax(b1).cwiseMax(b2).cwiseMax(b3);
    I.mid[j] = 0.25 * (b0 + b1 + b2 + b3);
    I.rho[j] = std::max({(b0 - I.mid[j]).norm(), (b1 - I.mid[j]).norm(), (b2 - I.mid[j]).norm(),
                         (b3 - I.mid[j]).norm()});
    const double inflate = std::max(colon.radius_m(j), colon.radius_m(j + 1)) + m.contact.query_margin_m;
    const Vec3 lo = I.lo[j].array() - inflate, hi = I.hi[j].array() + inflate;
    I.colon_boxes[j]->side = hi - lo;
    I.colon_boxes[j]->computeLocalAABB();
    I.colon_objs[j]->setTranslation(0.5 * (lo + hi));
    I.colon_objs[j]->computeAABB();
  }
  for (int k = 0; k < m.scope.segment_count; ++k) {
    I.scope_objs[k]->setTranslation(k < s.scope.inside ? s.scope.p_W[k] : Vec3(1e3 + k, 1e3, 1e3));
    I.scope_objs[k]->computeAABB();
  }
  I.colon_mgr->update();
  I.scope_mgr->update();
  I.pairs.clear();
  PairCollector collector{&I.pairs};
  I.colon_mgr->collide(I.scope_mgr.get(), &collector, collectPair);
  // Candidates grouped by scope segment (a counting sort), each group in ascending colon
  // segment order: the result does not depend on the tree's traversal order.
  const int K = m.scope.segment_count;
  std::fill(I.first.begin(), I.first.end(), 0);
  for (const auto& pr : I.pairs) ++I.first[pr.second + 1];
  for (int k = 0; k < K; ++k) I.first[k + 1] += I.first[k];
  I.grouped.resize(I.pairs.size());
  I.fill.assign(I.first.begin(), I.first.end() - 1);
  for (const auto& pr : I.pairs) I.grouped[I.fill[pr.second]++] = pr;
  for (int k = 0; k < K; ++k)
    std::sort(I.grouped.begin() + I.first[k], I.grouped.begin() + I.first[k + 1]);
  I.pairs.swap(I.grouped);

  // Narrowphase per slice: first the slice's centre on the scope axis, from the anus to the
  // tip. The scope runs inside the colon from the anus, so a slice lies next to the same
  // slice of its proximal neighbour (h along the scope) along the colon too. When its
  // tracked location is a far part of the colon from the neighbour's (the tracking kept
  // another part lying against the one the scope is in: docs/hardening.md, "Contact
  // tracking") and the centre lies deeper in the lumen next to the neighbour's location
  // (and within reach of it), that lumen is the slice's: the far-part rule of
  // nearestRobust then keeps its points there.
  const int P = static_cast<int>(m.scope.interaction_points_S.size());
  const int per_slice = m.scope.params.points_per_slice;
  const int slices = P / per_slice;
  I.axes.assign(static_cast<size_t>(s.scope.inside) * slices, Nearest());
  I.moved.assign(I.axes.size(), 0);
  for (int k = s.scope.inside - 1; k >= 0; --k) {
    for (int sl = 0; sl < slices; ++sl) {
      const int first = sl * per_slice;
      const Vec3 centre = s.scope.p_W[k] + s.scope.R_WS[k] * Vec3(0, 0, m.scope.interaction_points_S[first].z());
      Nearest axis = nearestRobust(m, centre, s.track[k * P + first].colon_segment, I.first[k], I.first[k + 1]);
      const Nearest before = k + 1 < s.scope.inside ? I.axes[(k + 1) * slices + sl] : Nearest();
      if (axis.j >= 0 && before.j >= 0) {
        const double ds = std::abs(colon.arclengthAt(axis.j, axis.p) - colon.arclengthAt(before.j, before.p));
        if (ds > m.contact.self_neighbour_radii * colon.radiusAt(before.j, before.p)) {
          const Nearest path = walkToNearest(I.cubics, centre, before.j);
          const double path_depth = path.d - colon.radiusAt(path.j, path.p);
          if (path_depth <= m.contact.query_margin_m && path_depth < axis.d - colon.radiusAt(axis.j, axis.p)) {
            axis = path;
            I.moved[k * slices + sl] = 1;
          }
        }
      }
      I.axes[k * slices + sl] = axis;
    }
  }
  // Then each slice's points, from the tip: when the whole ring is provably inside the
  // lumen (centre distance + scope radius <= the smallest nearby radius) no interaction
  // point of the slice can touch the wall: skip it.
  s.wall.clear();
  for (int k = 0; k < s.scope.inside; ++k) {
    const int c0 = I.first[k], c1 = I.first[k + 1];
    for (int first = 0; first < P; first += per_slice) {
      const Nearest& axis = I.axes[k * slices + first / per_slice];
      const bool moved = I.moved[k * slices + first / per_slice];
      double r_min = -kInf;  // the smallest lumen radius around the slice's location [m]
      Vec3 axis_point = Vec3::Zero();
      if (axis.j >= 0) {
        r_min = kInf;
        for (int i = std::max(0, axis.j - 1); i <= std::min(colon.n - 1, axis.j + 2); ++i)
          r_min = std::min(r_min, colon.radius_m(i));
        if (axis.d + m.scope.radius_m <= r_min) {
          for (int i = first; i < first + per_slice; ++i) s.track[k * P + i] = {axis.j, axis.p};
          continue;
        }
        axis_point = I.cubics[axis.j].at(axis.p);
      }
      for (int i = first; i < first + per_slice; ++i) {
        const Vec3 x = interactionPoint(m.scope, s.scope, k, i);
        WallTrack& track = s.track[k * P + i];
        // The same test per point: the spline point nearest the slice's centre is at most
        // |x - axis_point| from x, so x is inside the lumen when that is within r_min (the
        // points on the side of the scope away from the wall).
        if ((x - axis_point).squaredNorm() <= r_min * r_min && r_min > 0) {
          track = {axis.j, axis.p};
          continue;
        }
        const int start = (track.colon_segment >= 0 && !moved) ? track.colon_segment : axis.j;
        const Nearest best = nearestRobust(m, x, start, c0, c1);
        track = {best.j, best.p};
        recordIfOutside(m, I.cubics, k, i, x, best, s.wall);
      }
    }
  }
  resetOutsideTracks(m, s);
}

Nearest FclContactQuery::nearestRobust(const WorldModel& m, const Vec3& x, int start, int c0, int c1) {
  Impl& I = *impl_;
  const ColonModel& colon = m.colon;
  const int nseg = colon.n - 1;
  // 1. Walk along the spline from the start segment (the tracked location) to the local
  //    minimum of the distance.
  const Nearest local = walkToNearest(I.cubics, x, start);
  // 2. Other parts of the colon near x (broadphase candidates off the walked stretch),
  //    closest bounds first, skipping those whose bounds are farther than the best so far.
  I.order.clear();
  for (int c = c0; c < c1; ++c) {
    const int j = I.pairs[c].first;
    if (local.j >= 0 && std::abs(j - local.j) <= 1) continue;
    // Two lower bounds of the distance to the segment: its box (squared, no root unless
    // it passes) and its ball.
    const double box2 = (I.lo[j] - x).cwiseMax(x - I.hi[j]).cwiseMax(0.0).squaredNorm();
    if (!(box2 < local.d * local.d)) continue;
    const double bound = std::max(std::sqrt(box2), (x - I.mid[j]).norm() - I.rho[j]);
    if (bound < local.d) I.order.emplace_back(bound, j);
  }
  std::sort(I.order.begin(), I.order.end());
  Nearest other;
  for (const auto& [bound, j] : I.order) {
    if (bound >= std::min(other.d, local.d)) break;
    consider(I.cubics, j, x, other);
  }
  if (local.j < 0) {
    if (other.j >= 0) return other;
    Nearest all;  // nothing tracked and nothing near: the paper's scan
    for (int j = 0; j < nseg; ++j) consider(I.cubics, j, x, all);
    return all;
  }
  if (other.j < 0 || other.d >= local.d) return local;
  // 3. Another part is nearer. It takes over unless it is a different part of the colon
  //    (far in arclength: the other side of a loop) while x is still within reach of the
  //    tracked lumen.
  const double ds = std::abs(colon.arclengthAt(other.j, other.p) - colon.arclengthAt(local.j, local.p));
  const bool far_part = ds > m.contact.self_neighbour_radii * colon.radiusAt(local.j, local.p);
  const double reach = colon.radiusAt(local.j, local.p) + m.contact.query_margin_m;
  return (far_part && local.d <= reach) ? local : other;
}

void FclContactQuery::findSelfContacts(const WorldModel& m, WorldState& s) {
  Impl& I = *impl_;
  for (int i = 0; i < m.colon.n; ++i) {
    I.sphere_objs[i]->setTranslation(s.colon.q.col(i));
    I.sphere_objs[i]->computeAABB();
  }
  I.sphere_mgr->update();
  I.pairs.clear();
  PairCollector collector{&I.pairs};
  I.sphere_mgr->collide(&collector, collectPair);
  for (auto& pr : I.pairs)
    if (pr.first > pr.second) std::swap(pr.first, pr.second);
  std::sort(I.pairs.begin(), I.pairs.end());
  s.self.clear();
  SelfContact c;
  for (const auto& [a, b] : I.pairs)
    if (selfOverlap(m, s.colon, a, b, &c)) s.self.push_back(c);
}

std::unique_ptr<ContactQuery> makeContactQuery(const WorldModel& model, const std::string& mode) {
  if (mode == "scan") return std::make_unique<ScanContactQuery>(model);
  if (mode == "fcl") return std::make_unique<FclContactQuery>(model);
  if (mode.rfind("fcl:", 0) == 0) return std::make_unique<FclContactQuery>(model, mode.substr(4));
  throw std::invalid_argument("unknown contact query mode '" + mode + "' (known: fcl, fcl:MANAGER, scan)");
}

}  // namespace colosim
