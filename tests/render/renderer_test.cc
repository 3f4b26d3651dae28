// Headless rendering through OSMesa: what the images show, measured on their pixels.
// Set COLOSIM_RENDER_DUMP=/some/dir to keep the images as PNG files for a look.
#include "render/renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <memory>

#include "render/offscreen_context.h"
#include "tests/fixture.h"
#include "tests/render/render_fixture.h"
#include "trainer/assets.h"

namespace colosim {
namespace {

double luminance(const uint8_t* p) { return (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) / 255.0; }

// Mean luminance over pixels whose distance from the image centre, in units of half the
// image height, lies in [r0, r1).
double meanInAnnulus(const Image& img, double r0, double r1) {
  double sum = 0;
  int count = 0;
  const double cx = 0.5 * img.width, cy = 0.5 * img.height, h = 0.5 * img.height;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double r = std::hypot(x + 0.5 - cx, y + 0.5 - cy) / h;
      if (r >= r0 && r < r1) sum += luminance(img.at(x, y)), ++count;
    }
  return sum / count;
}

double meanImage(const Image& img) { return meanInAnnulus(img, 0, 1e9); }

void dump(const Image& img, const std::string& name) {
  if (const char* dir = std::getenv("COLOSIM_RENDER_DUMP"))
    writePng(std::string(dir) + "/" + name + ".png", img);
}

class RenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ctx_ = new OffscreenContext(320, 240);
    renderer_ = new Renderer();
  }
  static void TearDownTestSuite() {
    delete renderer_;
    delete ctx_;
  }
  void SetUp() override { ctx_->resize(320, 240); }
  void TearDown() override {
    const std::vector<unsigned> errors = drainGlErrors();
    EXPECT_TRUE(errors.empty()) << "GL error 0x" << std::hex << (errors.empty() ? 0 : errors[0]);
  }
  static OffscreenContext* ctx_;
  static Renderer* renderer_;
};
OffscreenContext* RenderTest::ctx_ = nullptr;
Renderer* RenderTest::renderer_ = nullptr;

Image onboard(OffscreenContext& ctx, Renderer& r, const ColonModel& colon, const CameraPose& cam,
              const OnboardOptics& optics = {}) {
  const ScopeShape no_scope;
  r.drawOnboard(colon, colon.q_rest, no_scope, cam, Viewport{0, 0, ctx.width(), ctx.height()}, optics);
  EXPECT_TRUE(drainGlErrors().empty());
  return ctx.read();
}

// Looking down a straight colon from its axis: the far lumen is dark, the near wall all
// around is bright, as in a colonoscope image.
TEST_F(RenderTest, OnboardStraightColonDarkCentreBrightRing) {
  const ColonModel colon = test::straightColon(0.36, 0.02);
  for (bool barrel : {true, false}) {
    OnboardOptics optics;
    optics.barrel_distortion = barrel;
    const Image img =
        onboard(*ctx_, *renderer_, colon, lookAlong(Vec3(0, 0, 0.06), Vec3::UnitZ(), Vec3::UnitY()), optics);
    dump(img, barrel ? "onboard_straight" : "onboard_straight_rectilinear");
    const double centre = meanInAnnulus(img, 0, 0.12);
    const double ring = meanInAnnulus(img, 0.55, 0.95);
    // The centre looks 0.3 m down the lumen: a few % of the near wall's light.
    EXPECT_LT(centre, 0.1) << "barrel " << barrel;
    EXPECT_GT(ring, 0.3) << "barrel " << barrel;
    EXPECT_GT(ring, 5 * centre) << "barrel " << barrel;
    // Brightness rises monotonically from the centre outwards (annuli of 0.15 half-heights).
    double prev = -1;
    for (double r0 = 0; r0 < 0.6; r0 += 0.15) {
      const double m = meanInAnnulus(img, r0, r0 + 0.15);
      EXPECT_GT(m, prev) << "annulus at " << r0 << ", barrel " << barrel;
      prev = m;
    }
  }
}

// Moving the tip towards the wall (sideways from the axis, still looking along it) makes
// the image brighter: the tip light's irradiance falls off with distance.
TEST_F(RenderTest, OnboardBrighterNearTheWall) {
  const ColonModel colon = test::straightColon(0.36, 0.02);
  double prev = 0;
  for (double offset_m : {0.0, 0.008, 0.014}) {
    const Image img =
        onboard(*ctx_, *renderer_, colon, lookAlong(Vec3(offset_m, 0, 0.06), Vec3::UnitZ(), Vec3::UnitY()));
    const double m = meanImage(img);
    EXPECT_GT(m, prev * 1.05) << "offset " << offset_m;
    prev = m;
  }
  // And facing the wall head on, closer is brighter.
  prev = 0;
  for (double gap_m : {0.015, 0.008}) {
    const Image img = onboard(*ctx_, *renderer_, colon,
                              lookAlong(Vec3(0.02 - gap_m, 0, 0.15), Vec3::UnitX(), Vec3::UnitZ()));
    dump(img, "onboard_wall_" + std::to_string(static_cast<int>(gap_m * 1000)) + "mm");
    const double m = meanImage(img);
    EXPECT_GT(m, prev * 1.1) << "gap " << gap_m;
    prev = m;
  }
}

// A lens pressed into the wall (in the tissue, outside the drawn surface) sees red-out,
// never black: red everywhere, and much redder than the ordinary view a few mm back.
TEST_F(RenderTest, OnboardInTheTissueIsRedOut) {
  const ColonModel colon = test::straightColon(0.36, 0.02);
  auto redness = [](const Image& img) {  // mean of r - max(g, b) over the image [0, 1]
    double sum = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const uint8_t* p = const_cast<Image&>(img).at(x, y);
        sum += (p[0] - std::max(p[1], p[2])) / 255.0;
      }
    return sum / (img.width * img.height);
  };
  for (const Vec3& forward : {Vec3(1, 0, 0), Vec3(1, 0, 1), Vec3(-1, 0, 0.2)}) {
    const Image in_wall =
        onboard(*ctx_, *renderer_, colon, lookAlong(Vec3(0.0225, 0, 0.15), forward.normalized(), Vec3::UnitZ()));
    dump(in_wall, "onboard_in_tissue");
    int dark = 0;
    for (int y = 0; y < in_wall.height; ++y)
      for (int x = 0; x < in_wall.width; ++x) dark += luminance(const_cast<Image&>(in_wall).at(x, y)) < 0.02;
    EXPECT_EQ(dark, 0) << "forward " << forward.transpose();
    EXPECT_GT(redness(in_wall), 0.3) << "forward " << forward.transpose();
  }
  const Image in_lumen =
      onboard(*ctx_, *renderer_, colon, lookAlong(Vec3(0.012, 0, 0.15), Vec3(1, 0, 1).normalized(), Vec3::UnitZ()));
  EXPECT_LT(redness(in_lumen), 0.3);
}

// A lens a fraction of a millimetre from the wall (the soft wall lets the scope press
// close, and at a kink the drawn facets pass within a millimetre of it) still sees the
// wall: no pixel shows the lumen's black through a wall cut away by the near plane.
TEST_F(RenderTest, OnboardWallBesideTheLensIsNotCutAway) {
  const ColonModel colon = test::straightColon(0.36, 0.02);
  for (double gap_m : {0.0008, 0.0003}) {
    for (const Vec3& forward : {Vec3(1, 0, 0), Vec3(1, 0, 0.5)}) {
      // Between two folds (every 3 cm), where the wall is at the full radius.
      const Image img = onboard(*ctx_, *renderer_, colon,
                                lookAlong(Vec3(0.02 - gap_m, 0, 0.165), forward.normalized(), Vec3::UnitZ()));
      dump(img, "onboard_touching_" + std::to_string(static_cast<int>(gap_m * 1e4)));
      // Within 0.8 half-heights of the centre (34 deg off the axis) every ray meets the
      // wall within twice the gap; beyond, oblique rays may run down the lumen and out of its end.
      int black = 0;
      const double cx = 0.5 * img.width, cy = 0.5 * img.height, h = 0.5 * img.height;
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
          if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) < 0.8 * h) black += luminance(img.at(x, y)) < 0.02;
      EXPECT_EQ(black, 0) << "gap " << gap_m << ", forward " << forward.transpose();
    }
  }
}

// Per-vertex distortion draws a facet as the straight-edged triangle between its
// projected vertices, which misses much of a facet that spans a wide angle next to the
// lens (on the outside of a kink the rings fan out into facets ~12 mm long). A coarse
// colon (one ring per 15 mm segment, 8 facets around) seen from 1 mm beside its wall
// shows wall, not the lumen's black, all over the centre of the image.
TEST_F(RenderTest, OnboardLongFacetsBesideTheLensLeaveNoHoles) {
  TubeOptions coarse;
  coarse.samples_per_segment = 1;
  coarse.sides = 8;
  coarse.haustra = false;
  Renderer r(coarse);
  const ColonModel colon = test::straightColon(0.36, 0.02);
  // Beside the middle of a facet (between two of the 8 vertices around, between rings).
  const double apothem_m = 0.02 * std::cos(3.14159265358979323846 / 8);
  const Vec3 across(std::cos(3.14159265358979323846 / 8), std::sin(3.14159265358979323846 / 8), 0);
  for (const Vec3& forward : {Vec3(across + Vec3(0, 0, 1)), Vec3(across + Vec3(0, 0, -0.3)), across}) {
    const Image img = onboard(*ctx_, r, colon,
                              lookAlong(Vec3((apothem_m - 0.001) * across + Vec3(0, 0, 0.1575)),
                                        forward.normalized(), Vec3::UnitZ()));
    dump(img, "onboard_long_facets");
    int black = 0;
    const double cx = 0.5 * img.width, cy = 0.5 * img.height, h = 0.5 * img.height;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) < 0.8 * h) black += luminance(img.at(x, y)) < 0.02;
    EXPECT_EQ(black, 0) << "forward " << forward.transpose();
  }
}

// The scope itself: behind the lens it is invisible (every pixel as without it), and
// retroflexed (the tip bent back to look at the shaft) it fills part of the image.
TEST_F(RenderTest, OnboardShowsTheScopeOnlyWhenRetroflexed) {
  const ColonModel colon = test::straightColon(0.36, 0.02);
  auto differing = [](const Image& a, const Image& b) {
    int n = 0;
    for (size_t k = 0; k < a.rgba.size(); k += 4)
      n += std::abs(a.rgba[k] - b.rgba[k]) + std::abs(a.rgba[k + 1] - b.rgba[k + 1]) > 6;
    return n;
  };
  for (bool barrel : {true, false}) {
    OnboardOptics optics;
    optics.barrel_distortion = barrel;
    // Straight insertion: the scope runs up the axis to the lens.
    ScopeShape straight;
    for (int i = 0; i <= 20; ++i) straight.centreline_m.push_back(Vec3(0, 0, 0.005 * i));
    const CameraPose ahead = lookAlong(Vec3(0, 0, 0.1), Vec3::UnitZ(), Vec3::UnitY());
    renderer_->drawOnboard(colon, colon.q_rest, straight, ahead, Viewport{0, 0, 320, 240}, optics);
    const Image with = ctx_->read();
    renderer_->drawOnboard(colon, colon.q_rest, ScopeShape{}, ahead, Viewport{0, 0, 320, 240}, optics);
    EXPECT_EQ(differing(with, ctx_->read()), 0) << "barrel " << barrel;
    // Retroflexed: up x = -9 mm to z = 0.2, a U-turn of 9 mm radius, down to z = 0.185.
    ScopeShape retro;
    for (double z = 0; z < 0.2; z += 0.005) retro.centreline_m.push_back(Vec3(-0.009, 0, z));
    for (int k = 0; k <= 12; ++k) {
      const double a = 3.14159265358979 * k / 12;
      retro.centreline_m.push_back(Vec3(-0.009 * std::cos(a), 0, 0.2 + 0.009 * std::sin(a)));
    }
    retro.centreline_m.push_back(Vec3(0.009, 0, 0.185));
    const CameraPose back = lookAlong(Vec3(0.009, 0, 0.185), -Vec3::UnitZ(), Vec3::UnitY());
    renderer_->drawOnboard(colon, colon.q_rest, retro, back, Viewport{0, 0, 320, 240}, optics);
    const Image shaft = ctx_->read();
    dump(shaft, barrel ? "onboard_retroflexed" : "onboard_retroflexed_rectilinear");
    renderer_->drawOnboard(colon, colon.q_rest, ScopeShape{}, back, Viewport{0, 0, 320, 240}, optics);
    EXPECT_GT(differing(shaft, ctx_->read()), 320 * 240 / 20) << "barrel " << barrel;
  }
}

// The scope-position display of an alpha loop: the scope's (green or yellow-tipped)
// pixels are present through the see-through colon, and they enclose a hole: flooding
// the other pixels from the image border leaves the loop's inside unreached.
TEST_F(RenderTest, GlobalViewShowsTheScopeLoop) {
  ctx_->resize(400, 400);
  const std::vector<Vec3> path = test::alphaLoopPath(0.06, 0.01);
  const ColonModel colon = test::colonThrough(test::toPoints(path), 0.016);
  ScopeShape scope;
  scope.centreline_m = path;
  Vec3 lo = colon.q_rest.rowwise().minCoeff(), hi = colon.q_rest.rowwise().maxCoeff();
  const OrbitCamera cam = frameBox(lo, hi, 1.0);
  renderer_->drawGlobal(colon, colon.q_rest, scope, cam, 400, 400);
  ASSERT_TRUE(drainGlErrors().empty());
  const Image img = ctx_->read();
  dump(img, "global_alpha_loop");

  const int W = img.width, H = img.height;
  std::vector<char> scope_px(W * H, 0), reached(W * H, 0);
  int n_scope = 0, n_colon = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const uint8_t* p = img.at(x, y);
      const bool green = p[1] > p[0] + 40 && p[1] > p[2] + 40;
      const bool tip = p[0] > 150 && p[1] > 120 && p[2] < 90;
      scope_px[y * W + x] = green || tip;
      n_scope += green || tip;
      n_colon += p[0] > p[1] + 20 && p[0] > 60;  // pinkish wall
    }
  EXPECT_GT(n_scope, 0.01 * W * H);
  EXPECT_GT(n_colon, 0.01 * W * H) << "the colon should be visible too";
  std::deque<int> queue;
  auto push = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= W || y >= H) return;
    const int k = y * W + x;
    if (reached[k] || scope_px[k]) return;
    reached[k] = 1;
    queue.push_back(k);
  };
  for (int x = 0; x < W; ++x) push(x, 0), push(x, H - 1);
  for (int y = 0; y < H; ++y) push(0, y), push(W - 1, y);
  while (!queue.empty()) {
    const int k = queue.front();
    queue.pop_front();
    push(k % W + 1, k / W), push(k % W - 1, k / W), push(k % W, k / W + 1), push(k % W, k / W - 1);
  }
  int enclosed = 0;
  for (int k = 0; k < W * H; ++k) enclosed += !reached[k] && !scope_px[k];
  EXPECT_GT(enclosed, 0.02 * W * H) << "no hole enclosed by the scope: the loop is not visible";
  // The loop's centre (0, 0, 0.12) projects into that hole.
  const Eigen::Vector4f c = perspectiveMatrix(cam.fov_y_deg * 3.14159265358979 / 180, 1.0, 0.01, 10) *
                            viewMatrix(cam.pose()) * Eigen::Vector4f(0, 0, 0.12f, 1);
  const int px = static_cast<int>((c.x() / c.w() * 0.5 + 0.5) * W);
  const int py = static_cast<int>((0.5 - c.y() / c.w() * 0.5) * H);
  ASSERT_TRUE(px >= 0 && px < W && py >= 0 && py < H);
  EXPECT_FALSE(reached[py * W + px]) << "the loop centre is reachable from the border";
}

// Any view at any size exports as a valid PNG of that size holding the image read back.
TEST_F(RenderTest, PngExportAtRequestedSize) {
  test::TempDir dir;
  const ColonModel colon = test::straightColon();
  ScopeShape scope;
  for (int i = 0; i <= 10; ++i) scope.centreline_m.push_back(Vec3(0, 0, 0.006 * i));
  for (auto [w, h] : {std::pair{317, 203}, std::pair{64, 48}, std::pair{1024, 768}}) {
    ctx_->resize(w, h);
    renderer_->drawOnboard(colon, colon.q_rest, scope,
                           lookAlong(Vec3(0, 0, 0.06), Vec3::UnitZ(), Vec3::UnitY()), w, h);
    const Image on = ctx_->read();
    writePng(dir.file("onboard.png"), on);
    const Image back = readPng(dir.file("onboard.png"));
    EXPECT_EQ(back.width, w);
    EXPECT_EQ(back.height, h);
    EXPECT_EQ(back.rgba, on.rgba);
    renderer_->drawGlobal(colon, colon.q_rest, scope,
                          frameBox(Vec3(-0.02, -0.02, 0), Vec3(0.02, 0.02, 0.36), static_cast<double>(w) / h),
                          w, h);
    const Image gl = ctx_->read();
    writePng(dir.file("global.png"), gl);
    EXPECT_EQ(readPng(dir.file("global.png")).rgba, gl.rgba);
    EXPECT_TRUE(drainGlErrors().empty()) << w << " x " << h;
  }
}

// Split view into one framebuffer: each half shows its own view and nothing else.
// The render scale (colosim train's cheaper views): drawn smaller and stretched onto the
// same viewport, the image keeps its look (same brightness per annulus within a few %),
// stays in its viewport in a split screen, and out-of-range scales are refused.
TEST_F(RenderTest, RenderScaleKeepsTheImageAndItsViewport) {
  const ColonModel colon = test::straightColon(0.36, 0.02);
  const CameraPose cam = lookAlong(Vec3(0.006, 0, 0.06), Vec3::UnitZ(), Vec3::UnitY());
  const Image full = onboard(*ctx_, *renderer_, colon, cam);
  OnboardOptics scaled;
  scaled.render_scale = 0.6;
  const Image small = onboard(*ctx_, *renderer_, colon, cam, scaled);
  dump(small, "onboard_scale_0.6");
  ASSERT_EQ(small.width, full.width);
  for (double r0 = 0; r0 < 0.9; r0 += 0.15) {
    const double a = meanInAnnulus(full, r0, r0 + 0.15), b = meanInAnnulus(small, r0, r0 + 0.15);
    EXPECT_NEAR(b, a, 0.02 + 0.05 * a) << "annulus at " << r0;
  }
  // Split screen: the scaled global view on the right leaves the left half as drawn.
  ctx_->resize(400, 200);
  const ScopeShape scope{{Vec3(0, 0, 0), Vec3(0, 0, 0.06)}, 0.0065};
  renderer_->drawOnboard(colon, colon.q_rest, scope, cam, Viewport{0, 0, 200, 200}, scaled);
  const Image left_only = ctx_->read();
  GlobalStyle style;
  style.render_scale = 0.5;
  renderer_->drawGlobal(colon, colon.q_rest, scope, frameBox(Vec3(-0.02, -0.02, 0), Vec3(0.02, 0.02, 0.36), 1.0),
                        Viewport{200, 0, 200, 200}, style);
  const Image both = ctx_->read();
  int differing = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      for (int c = 0; c < 3; ++c) differing += left_only.at(x, y)[c] != both.at(x, y)[c];
  EXPECT_EQ(differing, 0);
  EXPECT_NEAR(both.at(399, 0)[2], std::lround(style.background[2] * 255), 1);
  for (double bad : {0.0, 0.2, 1.5, std::nan("")}) {
    OnboardOptics o;
    o.render_scale = bad;
    EXPECT_THROW(renderer_->drawOnboard(colon, colon.q_rest, scope, cam, Viewport{0, 0, 200, 200}, o),
                 std::invalid_argument);
  }
}

TEST_F(RenderTest, SplitViewportsDoNotOverlap) {
  ctx_->resize(400, 200);
  const ColonModel colon = test::straightColon();
  const ScopeShape scope{{Vec3(0, 0, 0), Vec3(0, 0, 0.06)}, 0.0065};
  renderer_->drawGlobal(colon, colon.q_rest, scope,
                        frameBox(Vec3(-0.02, -0.02, 0), Vec3(0.02, 0.02, 0.36), 1.0),
                        Viewport{200, 0, 200, 200});
  renderer_->drawOnboard(colon, colon.q_rest, scope,
                         lookAlong(Vec3(0, 0, 0.06), Vec3::UnitZ(), Vec3::UnitY()), Viewport{0, 0, 200, 200});
  const Image img = ctx_->read();
  dump(img, "split");
  // The global view's background colour survives in the right half's corner.
  const uint8_t* corner = img.at(399, 0);
  const GlobalStyle style;
  EXPECT_NEAR(corner[2], std::lround(style.background[2] * 255), 1);
  // The onboard left half is the same as a full-size onboard render of that size.
  ctx_->resize(200, 200);
  renderer_->drawOnboard(colon, colon.q_rest, scope,
                         lookAlong(Vec3(0, 0, 0.06), Vec3::UnitZ(), Vec3::UnitY()), 200, 200);
  const Image alone = ctx_->read();
  int differing = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      for (int c = 0; c < 3; ++c) differing += std::abs(alone.at(x, y)[c] - img.at(x, y)[c]) > 2;
  EXPECT_EQ(differing, 0);
}

// The onboard view with the cull and the level of detail looks like the full draw of
// every strip at full detail: in the adult colon at 640 x 480, from tips along the colon
// looking ahead and back, and one beside the wall. Per pixel and channel: the mean
// absolute difference and the share of pixels off by more than 24 of 255.
// COLOSIM_RENDER_DUMP keeps the farthest pose's two images.
TEST_F(RenderTest, ReducedDetailLooksLikeTheFullDraw) {
  const Parameters params = loadParameters(test::asset("params/default.json"));
  const ColonModel colon = loadColonModel(test::asset("anatomy/adult.json"), params);
  ctx_->resize(640, 480);
  OnboardOptics full;
  full.reduce_detail = false;
  int poses = 0;
  for (double s_m : {0.2, 0.45, 0.8, 1.2}) {
    int j = 0;
    while (j + 2 < colon.n && colon.arclengthAt(j + 1, 0) < s_m) ++j;
    const Vec3 p = splinePoint(colon.q_rest, j, 0.5), t = splineTangent(colon.q_rest, j, 0.5).normalized();
    for (int view = 0; view < 3; ++view) {
      Vec3 eye = p, fwd = t;
      if (view == 1) fwd = -t;
      if (view == 2) eye = p + 0.6 * colon.radiusAt(j, 0.5) * t.unitOrthogonal();
      const CameraPose cam = lookAlong(eye, fwd, Vec3::UnitY());
      const Image reduced = onboard(*ctx_, *renderer_, colon, cam);
      const Image reference = onboard(*ctx_, *renderer_, colon, cam, full);
      long sum = 0;
      int off = 0;
      for (int y = 0; y < reduced.height; ++y)
        for (int x = 0; x < reduced.width; ++x) {
          int worst = 0;
          for (int c = 0; c < 3; ++c) {
            const int d = std::abs(reduced.at(x, y)[c] - reference.at(x, y)[c]);
            sum += d;
            worst = std::max(worst, d);
          }
          off += worst > 24;
        }
      const double mean = static_cast<double>(sum) / (3.0 * reduced.width * reduced.height);
      const double share = static_cast<double>(off) / (reduced.width * reduced.height);
      if (view == 0 && s_m == 1.2) dump(reduced, "onboard_reduced_detail"), dump(reference, "onboard_full_detail");
      // Written with mean differences up to 0.06 and shares up to 0.004 %. Coarser settings
      // (every n-th ring with n <= (d / 3 cm)^2, every 2nd side beyond 8 cm) visibly
      // reshaped the far folds: means up to 0.28, shares up to 0.47 %.
      EXPECT_LT(mean, 0.2) << "s " << s_m << " view " << view;
      EXPECT_LT(share, 0.0005) << "s " << s_m << " view " << view;
      ++poses;
    }
  }
  EXPECT_EQ(poses, 12);
}


// The context's read copies OSMesa's own buffer instead of calling glReadPixels: the two
// give the same bytes, for the onboard view (per-vertex distortion and, next to the wall,
// the exact pass through a framebuffer object), the global view and a resized context,
// and an image read into again takes each new size.
TEST_F(RenderTest, ReadingTheContextsBufferGivesWhatGlReadPixelsGives) {
  const ColonModel colon = test::straightColon(0.36, 0.02);
  const ScopeShape no_scope;
  Image img;
  int frames = 0;
  for (const auto& [w, h] : {std::pair{320, 240}, std::pair{200, 150}, std::pair{401, 203}}) {
    ctx_->resize(w, h);
    for (double off_axis_m : {0.0, 0.0195}) {  // on the axis; 0.5 mm from the wall: the exact pass
      const CameraPose cam = lookAlong(Vec3(off_axis_m, 0, 0.06), Vec3(0.3, 0.1, 1).normalized(), Vec3::UnitY());
      renderer_->drawOnboard(colon, colon.q_rest, no_scope, cam, Viewport{0, 0, w, h});
      ctx_->read(img);
      const Image reference = readFramebuffer(Viewport{0, 0, w, h});
      ASSERT_EQ(img.width, w);
      ASSERT_EQ(img.height, h);
      EXPECT_TRUE(img.rgba == reference.rgba) << w << " x " << h << ", " << off_axis_m << " m off axis";
      EXPECT_GT(meanImage(img), 0.01);  // something was drawn
      ++frames;
    }
    renderer_->drawGlobal(colon, colon.q_rest, no_scope,
                          frameBox(Vec3(-0.02, -0.02, 0), Vec3(0.02, 0.02, 0.36), static_cast<double>(w) / h), w, h);
    ctx_->read(img);
    EXPECT_TRUE(img.rgba == readFramebuffer(Viewport{0, 0, w, h}).rgba) << w << " x " << h << ", global";
    EXPECT_TRUE(img.rgba == ctx_->read().rgba);
    ++frames;
  }
  EXPECT_EQ(frames, 9);
}

}  // namespace
}  // namespace colosim
