#include "render/tube_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/numbers.h"

namespace colosim {

namespace {

// Fraction of the distance to a neighbouring ring's plane a vertex may reach (see
// buildColonMesh): below 1 so consecutive rings stay apart by a margin.
constexpr double kRingPlaneReach = 0.95;

// Two triangles per quad between ring i and ring i + 1.
void addRingIndices(int rings, int ring_vertices, std::vector<uint32_t>& indices) {
  for (int i = 0; i + 1 < rings; ++i) {
    for (int j = 0; j + 1 < ring_vertices; ++j) {
      const uint32_t a = i * ring_vertices + j, b = a + ring_vertices;
      indices.insert(indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
}

// Vertex normals by central differences on the (ring, side) grid: n = d/d(along) x d/d(around),
// turned to point towards (inward = true) or away from the ring centre.
void gridNormals(const std::vector<Vec3>& centre, int rings, int rv, bool inward, std::vector<float>& v) {
  auto P = [&](int i, int j) {
    const float* p = &v[8 * (i * rv + j)];
    return Vec3(p[0], p[1], p[2]);
  };
  const int sides = rv - 1;
  for (int i = 0; i < rings; ++i) {
    const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, rings - 1);
    for (int j = 0; j < sides; ++j) {
      const Vec3 along = P(i1, j) - P(i0, j);
      const Vec3 around = P(i, (j + 1) % sides) - P(i, (j + sides - 1) % sides);
      Vec3 n = along.cross(around);
      const Vec3 to_centre = centre[i] - P(i, j);
      if (n.norm() < 1e-300) n = to_centre;
      n.normalize();
      if ((n.dot(to_centre) < 0) == inward) n = -n;
      for (int jj : {j, j == 0 ? sides : -1}) {
        if (jj < 0) continue;
        float* dst = &v[8 * (i * rv + jj) + 3];
        dst[0] = static_cast<float>(n.x()), dst[1] = static_cast<float>(n.y()),
        dst[2] = static_cast<float>(n.z());
      }
    }
  }
}

}  // namespace

void sampleColonRings(const ColonModel& model, const Points& q, const TubeOptions& options,
                      ColonRings& rings) {
  if (q.cols() != model.n || model.n < 2)
    throw std::invalid_argument("render: control points have " + std::to_string(q.cols()) +
                                " columns, the colon model " + std::to_string(model.n));
  if (!q.allFinite()) throw std::invalid_argument("render: control points are not finite");
  const int S = std::max(1, options.samples_per_segment);
  const int count = (model.n - 1) * S + 1;
  rings.centre_m.resize(count);
  rings.tangent.resize(count);
  rings.radius_m.resize(count);
  rings.s_rest_m.resize(count);
  rings.fold_weight.resize(count);

  // Fold weight per control point: 0 next to a rectum segment, else 1; linear within a
  // segment, then limited by the rest distance to the rectum so folds fade in smoothly.
  std::vector<double> s_rectum_end;  // rest arclength where each rectum stretch ends [m]
  std::vector<char> rectum(model.n - 1, 0);
  for (int j = 0; j + 1 < model.n; ++j) {
    const int r = model.segment_region.empty() ? -1 : model.segment_region[j];
    rectum[j] =
        r >= 0 && r < static_cast<int>(model.region_names.size()) && model.region_names[r] == "rectum";
  }
  for (int k = 0; k < count; ++k) {
    const int j = std::min(k / S, model.n - 2);
    const double p = static_cast<double>(k - j * S) / S;
    rings.centre_m[k] = splinePoint(q, j, p);
    rings.tangent[k] = splineTangent(q, j, p);
    rings.radius_m[k] = model.smoothRadiusAt(j, p);  // the renderer draws the folds itself
    rings.s_rest_m[k] = model.arclengthAt(j, p);
  }
  // Distance in rest arclength to the nearest rectum segment, by two sweeps over rings.
  std::vector<double> dist(count, 1e300);
  for (int k = 0; k < count; ++k) {
    const int j = std::min(k / S, model.n - 2);
    const bool in_rectum = rectum[j] || (k % S == 0 && j > 0 && rectum[j - 1]);
    if (in_rectum) dist[k] = 0;
  }
  for (int k = 1; k < count; ++k)
    dist[k] = std::min(dist[k], dist[k - 1] + rings.s_rest_m[k] - rings.s_rest_m[k - 1]);
  for (int k = count - 2; k >= 0; --k)
    dist[k] = std::min(dist[k], dist[k + 1] + rings.s_rest_m[k + 1] - rings.s_rest_m[k]);
  const double ramp = std::max(options.fold_ramp_m, 1e-9);
  for (int k = 0; k < count; ++k) {
    const double x = std::clamp(dist[k] / ramp, 0.0, 1.0);
    rings.fold_weight[k] = x * x * (3 - 2 * x);  // smoothstep
  }

  const Vec3 r0 = initialNormal(splineTangent(q, 0, 0.0), splineSecondDerivative(q, 0, 0.0));
  rotationMinimisingFrames(rings.centre_m, rings.tangent, r0, rings.frame);
}

double haustralRadius(double radius_m, double s_rest_m, double theta_rad, double fold_weight,
                      const TubeOptions& options) {
  if (!options.haustra || fold_weight <= 0) return radius_m;
  const double P = options.fold_period_m;
  const double phase = s_rest_m / P - std::floor(s_rest_m / P);
  const double d_m = std::min(phase, 1 - phase) * P;  // rest distance to the nearest fold [m]
  const double sn = std::sin(1.5 * theta_rad);
  const double taenia = 0.35 + 0.65 * sn * sn;
  const double g = std::exp(-(d_m / options.fold_width_m) * (d_m / options.fold_width_m));
  return radius_m * (1 - options.fold_depth * fold_weight * taenia * g);
}

void buildColonMesh(const ColonRings& rings, const TubeOptions& options, TubeMesh& mesh) {
  const int count = static_cast<int>(rings.centre_m.size());
  const int sides = std::max(3, options.sides);
  const int rv = sides + 1;
  // The topology depends only on the ring and side counts: keep it from the last frame.
  const bool same_topology = mesh.rings == count && mesh.ring_vertices == rv &&
                             mesh.indices.size() == static_cast<size_t>(6) * (count - 1) * sides;
  mesh.rings = count;
  mesh.ring_vertices = rv;
  mesh.vertices.resize(static_cast<size_t>(count) * rv * TubeMesh::kFloatsPerVertex);
  std::vector<double> c(rv), s(rv);
  for (int j = 0; j < rv; ++j) {
    const double th = 2 * kPi * (j % sides) / sides;  // the seam vertex repeats j = 0 exactly
    c[j] = std::cos(th), s[j] = std::sin(th);
  }
  // haustralRadius factorised: the fold profile per ring, the taenia factor per side
  // (exp and sin once per ring and side, not per vertex: this runs every frame).
  std::vector<double> taenia(rv);
  for (int j = 0; j < rv; ++j) {
    const double sn = std::sin(1.5 * 2 * kPi * (j % sides) / sides);
    taenia[j] = 0.35 + 0.65 * sn * sn;
  }
  for (int i = 0; i < count; ++i) {
    const CurveFrame& f = rings.frame[i];
    // Keep the ring between its neighbours' planes. Ring i lies in the plane through c_i
    // normal to t_i; where the centreline bends tighter than the lumen radius, that plane
    // meets ring i + 1's (at the bend radius rho, on the inside of the bend) within the
    // lumen, and the wall beyond would fold over: the tube turns inside out. A vertex in
    // direction u (unit, in the ring's plane) stays behind the next plane,
    // (c_i + r u - c_{i+1}) . t_{i+1} < 0, while r < a / (u . t_{i+1}), a = (c_{i+1} - c_i) . t_{i+1},
    // and ahead of the previous one while r < b / (-u . t_{i-1}), b = (c_i - c_{i-1}) . t_{i-1}
    // (both rho on a circular bend). Each vertex is limited to kRingPlaneReach of these,
    // so the inside of a tight bend is drawn flattened at 0.95 rho from the centreline.
    const bool has_next = i + 1 < count, has_prev = i > 0;
    const Vec3 t_next = has_next ? rings.frame[i + 1].t : Vec3::Zero();
    const Vec3 t_prev = has_prev ? rings.frame[i - 1].t : Vec3::Zero();
    const double a_m = has_next ? std::max(0.0, (rings.centre_m[i + 1] - rings.centre_m[i]).dot(t_next)) : 0.0;
    const double b_m = has_prev ? std::max(0.0, (rings.centre_m[i] - rings.centre_m[i - 1]).dot(t_prev)) : 0.0;
    const float v = static_cast<float>(rings.s_rest_m[i] / options.texture_tile_m);
    // fold = depth * w * exp(-(d / width)^2), so r = R (1 - fold * taenia_j) as in haustralRadius.
    const double fold =
        haustralRadius(1.0, rings.s_rest_m[i], 0.5 * kPi / 1.5, rings.fold_weight[i], options);
    const double fold_amount = 1.0 - fold;  // at theta where taenia = 1
    const double R = rings.radius_m[i];
    for (int j = 0; j < rv; ++j) {
      const Vec3 u = c[j] * f.r + s[j] * f.s;
      double r = R * (1 - fold_amount * taenia[j]);
      const double toward_next = u.dot(t_next), toward_prev = -u.dot(t_prev);
      if (toward_next * r > kRingPlaneReach * a_m) r = kRingPlaneReach * a_m / toward_next;
      if (toward_prev * r > kRingPlaneReach * b_m) r = kRingPlaneReach * b_m / toward_prev;
      const Vec3 p = rings.centre_m[i] + r * u;
      float* dst = &mesh.vertices[8 * (static_cast<size_t>(i) * rv + j)];
      dst[0] = static_cast<float>(p.x()), dst[1] = static_cast<float>(p.y()),
      dst[2] = static_cast<float>(p.z());
      dst[6] = static_cast<float>(j) / sides;
      dst[7] = v;
    }
  }
  gridNormals(rings.centre_m, count, rv, /*inward=*/true, mesh.vertices);
  if (!same_topology) {
    mesh.indices.clear();
    addRingIndices(count, rv, mesh.indices);
  }
}

void buildColonMesh(const ColonModel& model, const Points& q, const TubeOptions& options, TubeMesh& mesh) {
  ColonRings rings;
  sampleColonRings(model, q, options, rings);
  buildColonMesh(rings, options, mesh);
}

bool insideLumen(const TubeMesh& mesh, const ColonRings& rings, const Vec3& x_m, double reach_m) {
  return probeLumen(mesh, rings, x_m, reach_m).inside;
}

LumenProbe probeLumen(const TubeMesh& mesh, const ColonRings& rings, const Vec3& x_m, double reach_m) {
  const int count = std::min(mesh.rings, static_cast<int>(rings.centre_m.size()));
  const int rv = mesh.ring_vertices;
  const double reach2 = reach_m * reach_m;
  // Nearest hit per ray (Moller-Trumbore) and whether it is seen from the lumen side.
  const Vec3 dirs[6] = {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
  double hit_t[6];
  bool hit_front[6];
  std::fill(hit_t, hit_t + 6, std::numeric_limits<double>::infinity());
  for (int i = 0; i + 1 < count; ++i) {
    if ((rings.centre_m[i] - x_m).squaredNorm() > reach2 && (rings.centre_m[i + 1] - x_m).squaredNorm() > reach2)
      continue;
    const size_t first = static_cast<size_t>(i) * (rv - 1) * 6;
    for (size_t t = first; t < first + static_cast<size_t>(rv - 1) * 6 && t + 2 < mesh.indices.size(); t += 3) {
      const Vec3 a = mesh.position(mesh.indices[t]);
      const Vec3 e1 = mesh.position(mesh.indices[t + 1]) - a, e2 = mesh.position(mesh.indices[t + 2]) - a;
      const Vec3 n = e1.cross(e2);  // counter-clockwise: points into the lumen
      const Vec3 to = x_m - a;
      for (int r = 0; r < 6; ++r) {
        const Vec3& d = dirs[r];
        const Vec3 p = d.cross(e2);
        const double det = e1.dot(p);
        if (std::abs(det) < 1e-18) continue;
        const double u = to.dot(p) / det;
        if (u < 0 || u > 1) continue;
        const Vec3 qv = to.cross(e1);
        const double v = d.dot(qv) / det;
        if (v < 0 || u + v > 1) continue;
        const double dist = e2.dot(qv) / det;
        if (dist <= 0 || dist >= hit_t[r]) continue;
        hit_t[r] = dist;
        hit_front[r] = n.dot(d) < 0;
      }
    }
  }
  int inside = 0, outside = 0;
  LumenProbe probe;
  probe.nearest_hit_m = std::numeric_limits<double>::infinity();
  for (int r = 0; r < 6; ++r) {
    if (!std::isfinite(hit_t[r])) continue;
    (hit_front[r] ? inside : outside) += 1;
    probe.nearest_hit_m = std::min(probe.nearest_hit_m, hit_t[r]);
  }
  probe.inside = inside > outside;
  return probe;
}

namespace {

// Whether ring i can appear in the view: closer than far_m and inside the view cone, both
// widened by the ring's bounding sphere.
bool ringInView(const ColonRings& rings, int i, const Vec3& eye_m, const Vec3& forward, double far_m,
                double cos_fov, double sin_fov) {
  const Vec3 d = rings.centre_m[i] - eye_m;
  const double r = rings.radius_m[i];  // folds only narrow the ring: r bounds it
  const double dist = d.norm();
  if (dist > far_m + r) return false;
  if (dist <= r) return true;  // the camera is inside this ring's sphere
  // Inside the cone widened by the ring's bounding sphere: the axis angle of d is at
  // most half_fov + asin(r / dist), i.e. cos(angle) >= cos(half_fov + asin(r / dist)).
  const double sa = r / dist, ca = std::sqrt(1 - sa * sa);
  return d.dot(forward) >= dist * (cos_fov * ca - sin_fov * sa);
}

// The triangles of the strip from ring a (every sa-th side) to ring b (every sb-th side);
// sa and sb divide the side count, one divides the other. Where they differ, each cell of
// the coarser ring is a fan: the finer ring's first half to the cell's first coarse
// vertex, a bridge triangle, the second half to its last.
void addStrip(int a, int b, int sa, int sb, int sides, int rv, std::vector<uint32_t>& out) {
  auto A = [&](int j) { return static_cast<uint32_t>(a * rv + j); };
  auto B = [&](int j) { return static_cast<uint32_t>(b * rv + j); };
  const int S = std::max(sa, sb), f = std::min(sa, sb), n = S / f;
  for (int j = 0; j < sides; j += S) {
    if (sa == sb) {
      out.insert(out.end(), {A(j), B(j), A(j + S), A(j + S), B(j), B(j + S)});
    } else if (sa < sb) {  // ring a finer
      for (int k = 0; k < n / 2; ++k) out.insert(out.end(), {A(j + k * f), B(j), A(j + (k + 1) * f)});
      out.insert(out.end(), {A(j + n / 2 * f), B(j), B(j + S)});
      for (int k = n / 2; k < n; ++k) out.insert(out.end(), {A(j + k * f), B(j + S), A(j + (k + 1) * f)});
    } else {  // ring b finer
      for (int k = 0; k < n / 2; ++k) out.insert(out.end(), {A(j), B(j + k * f), B(j + (k + 1) * f)});
      out.insert(out.end(), {A(j), B(j + n / 2 * f), A(j + S)});
      for (int k = n / 2; k < n; ++k) out.insert(out.end(), {A(j + S), B(j + k * f), B(j + (k + 1) * f)});
    }
  }
}

}  // namespace

void visibleStrips(const ColonRings& rings, const Vec3& eye_m, const Vec3& forward, double far_m,
                   double half_fov_rad, std::vector<StripRun>& runs) {
  runs.clear();
  const int count = static_cast<int>(rings.centre_m.size());
  const double cos_fov = std::cos(half_fov_rad), sin_fov = std::sin(half_fov_rad);
  auto visible = [&](int i) { return ringInView(rings, i, eye_m, forward, far_m, cos_fov, sin_fov); };
  bool prev = count > 0 && visible(0);
  for (int i = 0; i + 1 < count; ++i) {
    const bool next = visible(i + 1);
    if (prev || next) {
      if (!runs.empty() && runs.back().end == i)
        ++runs.back().end;
      else
        runs.push_back({i, i + 1});
    }
    prev = next;
  }
}

void visibleDetailIndices(const ColonRings& rings, int rv, const Vec3& eye_m, const Vec3& forward, double far_m,
                          double half_fov_rad, const DetailOptions& detail, std::vector<uint32_t>& indices) {
  indices.clear();
  const int count = static_cast<int>(rings.centre_m.size());
  const int sides = rv - 1;
  if (count < 2 || sides < 1) return;
  const double cos_fov = std::cos(half_fov_rad), sin_fov = std::sin(half_fov_rad);
  // Blocks of kBlock strips (rings kBlock b .. kBlock (b + 1); the last may be shorter):
  // drawn when a ring of theirs is in view, at a detail by their nearest distance.
  constexpr int kBlock = 8;
  const int max_step = std::clamp(detail.max_ring_step, 1, kBlock);
  const int blocks = (count - 1 + kBlock - 1) / kBlock;
  std::vector<int> ring_step(blocks, 0), side_step(blocks, 0);  // 0: not drawn
  for (int b = 0; b < blocks; ++b) {
    const int first = kBlock * b, last = std::min(first + kBlock, count - 1);
    bool seen = false;
    double nearest = 1e300;
    for (int i = first; i <= last; ++i) {
      seen = seen || ringInView(rings, i, eye_m, forward, far_m, cos_fov, sin_fov);
      nearest = std::max(0.0, std::min(nearest, (rings.centre_m[i] - eye_m).norm() - rings.radius_m[i]));
    }
    if (!seen) continue;
    // Seen down the tube, a strip's height on screen falls as 1 / d^2.
    int step = 1;
    const double x = nearest / std::max(detail.full_detail_m, 1e-9);
    while (2 * step <= max_step && x * x >= 2 * step && (last - first) % (2 * step) == 0) step *= 2;
    ring_step[b] = step;
    side_step[b] = sides % 2 == 0 && nearest > detail.half_sides_m ? 2 : 1;
  }
  // A ring shared by two drawn blocks takes the finer block's sides.
  auto boundary = [&](int b, int other) {
    return other >= 0 && other < blocks && side_step[other] > 0 ? std::min(side_step[b], side_step[other])
                                                                  : side_step[b];
  };
  for (int b = 0; b < blocks; ++b) {
    if (side_step[b] == 0) continue;
    const int first = kBlock * b, last = std::min(first + kBlock, count - 1);
    const int s = side_step[b], s_first = boundary(b, b - 1), s_last = boundary(b, b + 1);
    for (int a = first; a < last; a += ring_step[b]) {
      const int c = a + ring_step[b];
      addStrip(a, c, a == first ? s_first : s, c == last ? s_last : s, sides, rv, indices);
    }
  }
}

void buildScopeMesh(const ScopeShape& scope, const TubeOptions& options, TubeMesh& mesh) {
  const int n = static_cast<int>(scope.centreline_m.size());
  if (n < 2) throw std::invalid_argument("render: the scope needs at least two centreline points");
  if (!(scope.radius_m > 0) || !std::isfinite(scope.radius_m))
    throw std::invalid_argument("render: the scope radius must be positive");
  for (const Vec3& p : scope.centreline_m)
    if (!p.allFinite()) throw std::invalid_argument("render: scope centreline is not finite");
  std::vector<Vec3> tangent(n);
  for (int i = 0; i < n; ++i)
    tangent[i] = scope.centreline_m[std::min(i + 1, n - 1)] - scope.centreline_m[std::max(i - 1, 0)];
  for (int i = 0; i < n; ++i)
    if (tangent[i].norm() < 1e-12) tangent[i] = i > 0 ? tangent[i - 1] : Vec3::UnitZ();
  std::vector<CurveFrame> frames;
  const Vec3 d2 =
      n >= 3 ? Vec3(scope.centreline_m[2] - 2 * scope.centreline_m[1] + scope.centreline_m[0]) : Vec3::Zero();
  rotationMinimisingFrames(scope.centreline_m, tangent, initialNormal(tangent[0], d2), frames);

  const int sides = std::max(3, options.scope_sides);
  const int rv = sides + 1;
  mesh.rings = n;
  mesh.ring_vertices = rv;
  // Ring vertices, then one centre vertex closing the tip.
  mesh.vertices.assign((static_cast<size_t>(n) * rv + 1) * TubeMesh::kFloatsPerVertex, 0.0f);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < rv; ++j) {
      const double th = 2 * kPi * (j % sides) / sides;
      const Vec3 p =
          scope.centreline_m[i] + scope.radius_m * (std::cos(th) * frames[i].r + std::sin(th) * frames[i].s);
      float* dst = &mesh.vertices[8 * (static_cast<size_t>(i) * rv + j)];
      dst[0] = static_cast<float>(p.x()), dst[1] = static_cast<float>(p.y()),
      dst[2] = static_cast<float>(p.z());
      dst[6] = static_cast<float>(j) / sides;
    }
  }
  gridNormals(scope.centreline_m, n, rv, /*inward=*/false, mesh.vertices);
  mesh.indices.clear();
  addRingIndices(n, rv, mesh.indices);
  const uint32_t tip = static_cast<uint32_t>(n) * rv;
  float* t = &mesh.vertices[8 * static_cast<size_t>(tip)];
  const Vec3& p = scope.centreline_m[n - 1];
  const Vec3 axis = frames[n - 1].t;
  t[0] = static_cast<float>(p.x()), t[1] = static_cast<float>(p.y()), t[2] = static_cast<float>(p.z());
  t[3] = static_cast<float>(axis.x()), t[4] = static_cast<float>(axis.y()),
  t[5] = static_cast<float>(axis.z());
  for (int j = 0; j < sides; ++j) {
    const uint32_t a = (n - 1) * rv + j;
    mesh.indices.insert(mesh.indices.end(), {a, a + 1, tip});
  }
}

}  // namespace colosim
