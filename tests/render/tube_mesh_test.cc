#include "render/tube_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "tests/fixture.h"
#include "tests/render/render_fixture.h"
#include "trainer/assets.h"
#include "core/numbers.h"

namespace colosim {
namespace {

class AdultMesh : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const Parameters params = loadParameters(test::asset("params/default.json"));
    model_ = new ColonModel(loadColonModel(test::asset("anatomy/adult.json"), params));
  }
  static void TearDownTestSuite() { delete model_; }
  static ColonModel* model_;
};
ColonModel* AdultMesh::model_ = nullptr;

TEST_F(AdultMesh, SizesSeamAndNormals) {
  const TubeOptions opt;
  ColonRings rings;
  sampleColonRings(*model_, model_->q_rest, opt, rings);
  TubeMesh mesh;
  buildColonMesh(rings, opt, mesh);
  ASSERT_EQ(mesh.rings, static_cast<int>(rings.centre_m.size()));
  ASSERT_EQ(mesh.ring_vertices, opt.sides + 1);
  ASSERT_EQ(mesh.vertexCount(), mesh.rings * mesh.ring_vertices);
  ASSERT_EQ(mesh.indices.size(), static_cast<size_t>(6 * (mesh.rings - 1) * opt.sides));
  for (uint32_t idx : mesh.indices) ASSERT_LT(idx, static_cast<uint32_t>(mesh.vertexCount()));
  for (int i = 0; i < mesh.rings; ++i) {
    const int first = i * mesh.ring_vertices, seam = first + opt.sides;
    // The seam vertex repeats the first one's position and normal, with u = 1 instead of 0.
    EXPECT_EQ(mesh.position(first), mesh.position(seam));
    EXPECT_EQ(mesh.normal(first), mesh.normal(seam));
    EXPECT_EQ(mesh.u(first), 0.0f);
    EXPECT_EQ(mesh.u(seam), 1.0f);
    for (int j = 0; j < mesh.ring_vertices; ++j) {
      const int v = first + j;
      EXPECT_NEAR(mesh.normal(v).norm(), 1.0, 1e-5);
      // The wall faces the lumen (where the onboard camera is).
      EXPECT_GT(mesh.normal(v).dot(rings.centre_m[i] - mesh.position(v)), 0.0) << "ring " << i;
    }
  }
}

// Every vertex sits at the fold-modulated radius in its ring's plane; the rectum has no
// folds (exactly the local radius), the other regions narrow at the folds.
TEST_F(AdultMesh, RadiusHaustraAndRectum) {
  const TubeOptions opt;
  ColonRings rings;
  sampleColonRings(*model_, model_->q_rest, opt, rings);
  TubeMesh mesh;
  buildColonMesh(rings, opt, mesh);
  int rectum_rings = 0;
  double min_ratio_outside = 1;
  for (int i = 0; i < mesh.rings; ++i) {
    const int seg = std::min(i / opt.samples_per_segment, model_->n - 2);
    const bool rectum = model_->region_names[model_->segment_region[seg]] == "rectum";
    for (int j = 0; j < opt.sides; ++j) {
      const Vec3 d = mesh.position(i * mesh.ring_vertices + j) - rings.centre_m[i];
      EXPECT_NEAR(d.dot(rings.frame[i].t), 0.0, 1e-6);
      const double r = d.norm();
      EXPECT_NEAR(r,
                  haustralRadius(rings.radius_m[i], rings.s_rest_m[i], 2 * kPi * j / opt.sides,
                                 rings.fold_weight[i], opt),
                  1e-6);
      if (rectum)
        EXPECT_NEAR(r, rings.radius_m[i], 1e-6) << "a fold in the rectum, ring " << i;
      else
        min_ratio_outside = std::min(min_ratio_outside, r / rings.radius_m[i]);
    }
    rectum_rings += rectum;
  }
  EXPECT_GT(rectum_rings, 50);
  EXPECT_LT(min_ratio_outside, 1 - 0.8 * opt.fold_depth);
  // Folds recur with the period in rest arclength: count narrowings in the transverse colon.
  int folds = 0;
  for (int i = 1; i + 1 < mesh.rings; ++i) {
    const int seg = std::min(i / opt.samples_per_segment, model_->n - 2);
    if (model_->region_names[model_->segment_region[seg]] != "transverse") continue;
    auto ratio = [&](int k) {
      return haustralRadius(1.0, rings.s_rest_m[k], kPi / 3, rings.fold_weight[k], opt);
    };
    if (ratio(i) < ratio(i - 1) && ratio(i) <= ratio(i + 1) && ratio(i) < 0.95) ++folds;
  }
  double transverse_m = 0;
  for (int j = 0; j + 1 < model_->n; ++j)
    if (model_->region_names[model_->segment_region[j]] == "transverse")
      transverse_m += model_->segment_length_m(j);
  EXPECT_NEAR(folds, transverse_m / opt.fold_period_m, 1.5);
}

// Texture coordinates follow the tissue: stretching the colon by 20 % moves the
// vertices but leaves every (u, v) unchanged; v is the rest arclength over the tile.
TEST_F(AdultMesh, TextureDoesNotSwimWhenStretched) {
  const TubeOptions opt;
  TubeMesh rest, stretched;
  buildColonMesh(*model_, model_->q_rest, opt, rest);
  buildColonMesh(*model_, Points(1.2 * model_->q_rest), opt, stretched);
  ASSERT_EQ(rest.vertexCount(), stretched.vertexCount());
  double moved = 0;
  for (int v = 0; v < rest.vertexCount(); ++v) {
    ASSERT_EQ(rest.u(v), stretched.u(v));
    ASSERT_EQ(rest.v(v), stretched.v(v));
    moved = std::max(moved, (rest.position(v) - stretched.position(v)).norm());
  }
  EXPECT_GT(moved, 0.05);
  const int last = rest.vertexCount() - 1;
  EXPECT_NEAR(rest.v(last), model_->length_m() / opt.texture_tile_m, 1e-4);
}

// The CPU cull never drops a strip the camera could see: brute force over every vertex
// of every culled strip, from cameras all along the colon looking both ways.
TEST_F(AdultMesh, VisibleStripsKeepsEverythingInView) {
  const TubeOptions opt;
  ColonRings rings;
  sampleColonRings(*model_, model_->q_rest, opt, rings);
  TubeMesh mesh;
  buildColonMesh(rings, opt, mesh);
  const double far_m = 0.3, half_fov = 70 * kPi / 180;
  std::vector<StripRun> runs;
  int culled_total = 0;
  for (size_t k = 5; k < rings.centre_m.size(); k += 97) {
    for (double dir : {1.0, -1.0}) {
      const Vec3 eye = rings.centre_m[k] + 0.5 * rings.radius_m[k] * rings.frame[k].r;
      const Vec3 fwd = dir * rings.frame[k].t;
      visibleStrips(rings, eye, fwd, far_m, half_fov, runs);
      std::vector<char> kept(mesh.rings - 1, 0);
      for (const StripRun& r : runs) {
        ASSERT_LT(r.first, r.end);
        for (int i = r.first; i < r.end; ++i) kept[i] = 1;
      }
      for (int i = 0; i + 1 < mesh.rings; ++i) {
        if (kept[i]) continue;
        ++culled_total;
        for (int ring : {i, i + 1})
          for (int j = 0; j < mesh.ring_vertices; ++j) {
            const Vec3 d = mesh.position(ring * mesh.ring_vertices + j) - eye;
            const bool in_view = d.norm() < far_m && d.dot(fwd) > d.norm() * std::cos(half_fov);
            ASSERT_FALSE(in_view) << "strip " << i << " culled but vertex " << j << " is in view";
          }
      }
    }
  }
  EXPECT_GT(culled_total, 1000) << "the cull should drop something";
}

// The level-of-detail triangles: from cameras along the colon, the drawn wall is closed
// where pairs of different detail meet (every edge inside the drawn part is shared by
// exactly two triangles, once in each direction: no T-junction cracks, one winding), the
// far part is drawn with fewer triangles, and everything the cull keeps is drawn.
TEST_F(AdultMesh, DetailIndicesCloseTheWallAndSaveTriangles) {
  const TubeOptions opt;
  ColonRings rings;
  sampleColonRings(*model_, model_->q_rest, opt, rings);
  TubeMesh mesh;
  buildColonMesh(rings, opt, mesh);
  const int rv = mesh.ring_vertices, sides = rv - 1;
  const double far_m = 0.3, half_fov = 70 * kPi / 180;
  std::vector<uint32_t> indices;
  std::vector<StripRun> runs;
  int coarse_views = 0;
  for (size_t k = 5; k < rings.centre_m.size(); k += 61) {
    for (double dir : {1.0, -1.0}) {
      const Vec3 eye = rings.centre_m[k] + 0.5 * rings.radius_m[k] * rings.frame[k].r;
      const Vec3 fwd = dir * rings.frame[k].t;
      visibleDetailIndices(rings, rv, eye, fwd, far_m, half_fov, DetailOptions{}, indices);
      ASSERT_EQ(indices.size() % 3, 0u);
      // Edges by (ring, side) with the seam's duplicate vertex folded onto side 0; which
      // strips the triangles cover; which rings are joined to rings before and after them.
      std::map<std::pair<std::pair<int, int>, std::pair<int, int>>, int> directed;
      std::vector<char> covered(mesh.rings, 0), before(mesh.rings, 0), after(mesh.rings, 0);
      auto key = [&](uint32_t v) {
        return std::make_pair(static_cast<int>(v) / rv, static_cast<int>(v) % rv % sides);
      };
      for (size_t t = 0; t < indices.size(); t += 3) {
        int r0 = mesh.rings, r1 = -1;
        for (int e = 0; e < 3; ++e) {
          const auto a = key(indices[t + e]), b = key(indices[t + (e + 1) % 3]);
          ASSERT_NE(a, b) << "degenerate triangle";
          ++directed[{a, b}];
          r0 = std::min(r0, a.first), r1 = std::max(r1, a.first);
        }
        for (int i = r0; i < r1; ++i) covered[i] = 1;
        before[r1] = after[r0] = 1;
      }
      // Every edge is drawn once in its direction and, inside the drawn wall, once in the
      // other: an unmatched edge is allowed only along a ring that is the end of a drawn run
      // (joined to one side only). A T-junction leaves unmatched edges along a ring joined
      // on both sides.
      for (const auto& [edge, n] : directed) {
        ASSERT_EQ(n, 1) << "edge drawn twice the same way";
        const auto& [a, b] = edge;
        if (directed.count({b, a})) continue;
        ASSERT_EQ(a.first, b.first) << "open edge across rings " << a.first << ", " << b.first;
        EXPECT_FALSE(before[a.first] && after[a.first]) << "crack along ring " << a.first;
      }
      // Every strip the strip cull keeps is drawn.
      visibleStrips(rings, eye, fwd, far_m, half_fov, runs);
      size_t full = 0;
      for (const StripRun& r : runs) {
        full += static_cast<size_t>(r.end - r.first) * 6 * sides;
        for (int i = r.first; i < r.end; ++i) EXPECT_TRUE(covered[i]) << "strip " << i << " left out";
      }
      if (indices.size() < full / 2) ++coarse_views;
    }
  }
  EXPECT_GT(coarse_views, 10) << "far strips should be drawn coarser";
}

// insideLumen against the wall as drawn: on the axis and just inside the wall inside;
// just beyond the wall outside, also in a fold, where the wall is closer than the
// unfolded radius (a point there is in the fold's tissue).
TEST(TubeMesh, InsideLumenFollowsTheDrawnWall) {
  const ColonModel model = test::straightColon(0.36, 0.02);
  ColonRings rings;
  sampleColonRings(model, model.q_rest, TubeOptions{}, rings);
  TubeMesh mesh;
  buildColonMesh(rings, TubeOptions{}, mesh);
  // On one side of the mesh, the rings in the middle third where the wall is nearest
  // (a fold) and farthest (between folds) from the axis.
  const int side = 5, rv = mesh.ring_vertices;
  int fold = -1, gap = -1;
  double r_fold = 1, r_gap = 0;
  for (int i = mesh.rings / 3; i < 2 * mesh.rings / 3; ++i) {
    const double r = (mesh.position(i * rv + side) - rings.centre_m[i]).norm();
    if (r < r_fold) r_fold = r, fold = i;
    if (r > r_gap) r_gap = r, gap = i;
  }
  ASSERT_LT(r_fold, r_gap - 0.003);  // folds narrow the lumen by millimetres
  auto at = [&](int ring, double r) -> Vec3 {
    return rings.centre_m[ring] + r * (mesh.position(ring * rv + side) - rings.centre_m[ring]).normalized();
  };
  EXPECT_TRUE(insideLumen(mesh, rings, rings.centre_m[mesh.rings / 2]));
  EXPECT_TRUE(insideLumen(mesh, rings, at(gap, r_gap - 0.0015)));
  EXPECT_FALSE(insideLumen(mesh, rings, at(gap, r_gap + 0.0015)));
  EXPECT_TRUE(insideLumen(mesh, rings, at(fold, r_fold - 0.0015)));
  EXPECT_FALSE(insideLumen(mesh, rings, at(fold, r_fold + 0.0015)));  // in the fold's tissue
  EXPECT_LT(r_fold + 0.0015, 0.02);  // ... though within the unfolded radius
  EXPECT_FALSE(insideLumen(mesh, rings, Vec3(0.2, 0, 0.13)));  // far outside: no wall in reach
  // The nearest ray hit: about the radius on the axis, and 1.5 mm to sqrt(3) x 1.5 mm
  // (the rays are axis-aligned, the wall is not) beside the wall between folds.
  const LumenProbe axis = probeLumen(mesh, rings, rings.centre_m[gap]);
  EXPECT_TRUE(axis.inside);
  EXPECT_GT(axis.nearest_hit_m, r_fold - 0.001);
  EXPECT_LT(axis.nearest_hit_m, 0.02 + 1e-4);
  const double beside = probeLumen(mesh, rings, at(gap, r_gap - 0.0015)).nearest_hit_m;
  EXPECT_GT(beside, 0.0015 - 2e-4);
  EXPECT_LT(beside, std::sqrt(3.0) * 0.0015 + 2e-4);
}

// A colon that turns 180 degrees around a bend of centreline radius bend_m [m] in the
// x-z plane: up +z, round the bend, back down; control points every step_m [m].
ColonModel hairpinColon(double bend_m, double radius_m, double step_m = 0.005) {
  std::vector<Vec3> p;
  const int legs = 12, k = std::max(2, static_cast<int>(std::ceil(kPi * bend_m / step_m)));
  for (int i = legs; i > 0; --i) p.push_back(Vec3(-bend_m, 0, -i * step_m));
  for (int i = 0; i <= k; ++i) p.push_back(Vec3(-bend_m * std::cos(kPi * i / k), 0, bend_m * std::sin(kPi * i / k)));
  for (int i = 1; i <= legs; ++i) p.push_back(Vec3(bend_m, 0, -i * step_m));
  return test::colonThrough(test::toPoints(p), radius_m);
}

// Smallest signed distance [m] of ring b's vertices from ring a's plane, measured along
// a's tangent times `sign` (+1: b should lie ahead of a, -1: behind).
double ringClearance(const TubeMesh& mesh, const ColonRings& rings, int a, int b, double sign) {
  double least = 1e300;
  for (int j = 0; j + 1 < mesh.ring_vertices; ++j)
    least = std::min(least,
                     sign * (mesh.position(b * mesh.ring_vertices + j) - rings.centre_m[a]).dot(rings.frame[a].t));
  return least;
}

// Where the centreline bends tighter than the lumen radius (a tip tenting the colon makes
// such kinks), rings at right angles to it would cross on the inside of the bend and turn
// the tube inside out. The rings stay ordered: every vertex of ring k + 1 lies ahead of
// ring k's plane and every vertex of ring k behind ring k + 1's, so consecutive strips
// cannot intersect. Gentle bends keep the full radius.
TEST(TubeMesh, RingsNeverCrossAtABendTighterThanTheLumen) {
  for (double bend_m : {0.01, 0.004}) {
    const ColonModel model = hairpinColon(bend_m, 0.02);
    for (bool haustra : {false, true}) {
      TubeOptions opt;
      opt.haustra = haustra;
      ColonRings rings;
      sampleColonRings(model, model.q_rest, opt, rings);
      TubeMesh mesh;
      buildColonMesh(rings, opt, mesh);
      for (int k = 0; k + 1 < mesh.rings; ++k) {
        ASSERT_GT(ringClearance(mesh, rings, k, k + 1, +1), 0.0) << "bend " << bend_m << ", ring " << k + 1 << " crosses ring " << k;
        ASSERT_GT(ringClearance(mesh, rings, k + 1, k, -1), 0.0) << "bend " << bend_m << ", ring " << k << " crosses ring " << k + 1;
      }
      // On the straight legs, away from the bend, every vertex keeps its radius.
      for (int i : {2, mesh.rings - 3})
        for (int j = 0; j < opt.sides; ++j)
          EXPECT_NEAR((mesh.position(i * mesh.ring_vertices + j) - rings.centre_m[i]).norm(),
                      haustralRadius(rings.radius_m[i], rings.s_rest_m[i], 2 * kPi * j / opt.sides,
                                     rings.fold_weight[i], opt),
                      1e-6);
    }
  }
}

TEST(TubeMesh, RejectsBadControlPoints) {
  const ColonModel model = test::straightColon();
  TubeMesh mesh;
  EXPECT_THROW(buildColonMesh(model, Points(3, model.n - 1), TubeOptions{}, mesh), std::invalid_argument);
  Points q = model.q_rest;
  q(1, 3) = std::nan("");
  EXPECT_THROW(buildColonMesh(model, q, TubeOptions{}, mesh), std::invalid_argument);
}

TEST(ScopeMesh, TubeAtTheScopeRadiusClosedAtTheTip) {
  ScopeShape scope;
  scope.centreline_m = test::alphaLoopPath();
  scope.radius_m = 0.0065;
  const TubeOptions opt;
  TubeMesh mesh;
  buildScopeMesh(scope, opt, mesh);
  const int n = static_cast<int>(scope.centreline_m.size());
  ASSERT_EQ(mesh.vertexCount(), n * (opt.scope_sides + 1) + 1);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < opt.scope_sides; ++j) {
      const int v = i * mesh.ring_vertices + j;
      const Vec3 d = mesh.position(v) - scope.centreline_m[i];
      EXPECT_NEAR(d.norm(), scope.radius_m, 1e-6);
      EXPECT_GT(mesh.normal(v).dot(d), 0.0);  // outward
    }
  }
  EXPECT_LT((mesh.position(mesh.vertexCount() - 1) - scope.centreline_m.back()).norm(), 1e-6);
  ScopeShape bad = scope;
  bad.centreline_m.resize(1);
  EXPECT_THROW(buildScopeMesh(bad, opt, mesh), std::invalid_argument);
  bad = scope;
  bad.radius_m = 0;
  EXPECT_THROW(buildScopeMesh(bad, opt, mesh), std::invalid_argument);
}

}  // namespace
}  // namespace colosim
