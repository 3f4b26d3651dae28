// Tube meshes of the colon and the scope (paper section 2.6: circles along the spline
// joined by facets). Pure data, no GL: rebuilt from the control points every frame and
// uploaded by the renderer.
#pragma once

#include <cstdint>
#include <vector>

#include "core/colon_model.h"
#include "render/frames.h"

namespace colosim {

/// The colonoscope's shape as the renderer needs it: points along its axis from the
/// anus (first) to the tip (last) [m], and its outer radius [m].
struct ScopeShape {
  std::vector<Vec3> centreline_m;
  double radius_m = 0.0065;  ///< a 13 mm adult colonoscope
};

/// Tunables of the tube meshes; defaults are what the views use.
struct TubeOptions {
  int samples_per_segment = 8;   ///< rings per spline segment (1.9 mm apart at 1.5 cm spacing)
  int sides = 32;                ///< facets around the colon
  int scope_sides = 16;          ///< facets around the scope
  bool haustra = true;           ///< haustral folds (never in the rectum)
  double fold_period_m = 0.03;   ///< rest arclength between two haustral folds [m]
  double fold_width_m = 0.0035;  ///< Gaussian half-width of a fold along the colon [m]
  double fold_depth = 0.25;      ///< a fold's narrowing as a fraction of the local radius [-]
  double fold_ramp_m = 0.015;    ///< folds fade in over this rest arclength after the rectum [m]
  double texture_tile_m = 0.08;  ///< rest arclength covered by one texture tile along [m]
};

/// A triangle mesh: interleaved float vertices (position [m] xyz, unit normal xyz,
/// texture uv) and triangle indices. Normals point into the lumen for the colon (the
/// side the onboard camera sees) and outwards for the scope.
struct TubeMesh {
  static constexpr int kFloatsPerVertex = 8;
  int rings = 0;          ///< rings along the tube
  int ring_vertices = 0;  ///< vertices per ring (sides + 1: the seam vertex is duplicated, u = 1)
  std::vector<float> vertices;
  std::vector<uint32_t> indices;

  int vertexCount() const { return static_cast<int>(vertices.size()) / kFloatsPerVertex; }
  Vec3 position(int v) const { return {vertices[8 * v], vertices[8 * v + 1], vertices[8 * v + 2]}; }
  Vec3 normal(int v) const { return {vertices[8 * v + 3], vertices[8 * v + 4], vertices[8 * v + 5]}; }
  float u(int v) const { return vertices[8 * v + 6]; }
  float v(int v) const { return vertices[8 * v + 7]; }
};

/// The colon's centreline sampled for the mesh: one entry per ring.
struct ColonRings {
  std::vector<Vec3> centre_m;       ///< spline point M_j(p) [m]
  std::vector<Vec3> tangent;        ///< dM/dp [m] (not normalised)
  std::vector<CurveFrame> frame;    ///< rotation-minimising frame
  std::vector<double> radius_m;     ///< lumen radius without folds [m]
  std::vector<double> s_rest_m;     ///< rest arclength [m]: folds and texture follow the tissue
  std::vector<double> fold_weight;  ///< 0 in the rectum, ramping to 1 [-]
};

/// Samples the spline through q (3 x model.n) [m] at options.samples_per_segment rings
/// per segment, with rotation-minimising frames started from the Frenet frame at the anus.
/// Throws std::invalid_argument if q does not have model.n columns or is not finite.
void sampleColonRings(const ColonModel& model, const Points& q, const TubeOptions& options,
                      ColonRings& rings);

/// Radius of the wall [m] at rest arclength s_rest_m and angle theta_rad around the ring:
///   r = R (1 - depth w m(theta) exp(-(d / width)^2)),
/// d the rest distance to the nearest fold (folds every fold_period_m), w the fold weight,
/// m(theta) = 0.35 + 0.65 sin^2(1.5 theta) the shallower fold at the three taeniae coli.
double haustralRadius(double radius_m, double s_rest_m, double theta_rad, double fold_weight,
                      const TubeOptions& options);

/// Whether x_m lies in the lumen of a colon mesh built by buildColonMesh from `rings`:
/// six rays from x_m (along +-x, +-y, +-z) against the mesh's triangles whose rings lie
/// within reach_m; a ray whose first hit is a wall facing into the lumen votes inside, one
/// that meets the wall from behind votes outside. Inside when the inside votes win. A
/// point in the tissue (a lens pressed into the soft wall or a fold, or beyond the
/// flattened inside of a kink) is outside. Rays that meet nothing do not vote;
/// no vote at all is outside.
bool insideLumen(const TubeMesh& mesh, const ColonRings& rings, const Vec3& x_m, double reach_m = 0.06);

/// insideLumen's answer, and the nearest of its six rays' first hits [m] (infinity when no
/// ray meets the wall within reach): at most sqrt(3) times the distance to the wall.
struct LumenProbe {
  bool inside = false;
  double nearest_hit_m = 0;
};
LumenProbe probeLumen(const TubeMesh& mesh, const ColonRings& rings, const Vec3& x_m, double reach_m = 0.06);

/// Builds the colon wall from sampled rings. Triangles are wound counter-clockwise seen
/// from the lumen (the front faces look inwards). Each vertex reaches at most 0.95 of the
/// way to the neighbouring rings' planes, so where the centreline bends tighter than the
/// lumen radius consecutive rings do not cross (the inside of the bend is flattened).
/// [out] mesh (its buffers are reused).
void buildColonMesh(const ColonRings& rings, const TubeOptions& options, TubeMesh& mesh);

/// sampleColonRings then buildColonMesh.
void buildColonMesh(const ColonModel& model, const Points& q, const TubeOptions& options, TubeMesh& mesh);

/// A run of consecutive strips [first, end) between rings (strip i joins ring i to i + 1).
struct StripRun {
  int first = 0, end = 0;
};

/// The strips of the colon mesh an onboard camera at eye_m looking along `forward` (unit)
/// with half field of view half_fov_rad (across the diagonal) can see: those with a ring
/// closer than far_m and inside the view cone, both widened by the ring's radius. A cheap
/// CPU cull so llvmpipe does not set up triangles it would clip. [out] runs, merged
/// where consecutive.
void visibleStrips(const ColonRings& rings, const Vec3& eye_m, const Vec3& forward, double far_m,
                   double half_fov_rad, std::vector<StripRun>& runs);

/// Level of detail of the onboard colon by distance (visibleDetailIndices): a facet far
/// from the lens covers few pixels, and llvmpipe pays per triangle and per vertex.
struct DetailOptions {
  /// Blocks of 8 strips whose nearest point (ring centre distance less the unfolded
  /// radius) lies at d from the eye are drawn with every n-th ring, n the largest power of
  /// 2 with n <= (d / full_detail_m)^2 and n <= max_ring_step: looking down the tube, a
  /// strip's height on screen falls as 1 / d^2 [m].
  /// (0.03 m with every 2nd side beyond 0.08 m visibly reshaped the folds 9-12 cm away.)
  double full_detail_m = 0.05;
  int max_ring_step = 8;  ///< 1, 2, 4 or 8
  /// Blocks farther than this are drawn with every 2nd side as well [m].
  double half_sides_m = 0.12;
};

/// Triangle indices into a colon mesh built by buildColonMesh from `rings` (ring_vertices
/// per ring) of what an onboard camera can see (visibleStrips' test, by pairs of strips),
/// with detail decreasing with distance (DetailOptions). Where pairs of different detail
/// meet, the finer ring is joined to the coarser one by fans, so the wall stays closed (no
/// T-junction cracks); triangles keep buildColonMesh's winding. [out] indices.
void visibleDetailIndices(const ColonRings& rings, int ring_vertices, const Vec3& eye_m, const Vec3& forward,
                          double far_m, double half_fov_rad, const DetailOptions& detail,
                          std::vector<uint32_t>& indices);

/// The scope as a tube along its centreline, closed at the tip. Throws
/// std::invalid_argument for fewer than two points, a non-positive radius or NaN.
void buildScopeMesh(const ScopeShape& scope, const TubeOptions& options, TubeMesh& mesh);

}  // namespace colosim
