#include "render/frames.h"

#include <gtest/gtest.h>

#include <cmath>

#include "render/tube_mesh.h"
#include "tests/fixture.h"
#include "trainer/assets.h"
#include "core/numbers.h"

namespace colosim {
namespace {

double angleBetween(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// Along the whole adult colon, sigmoid loop included, neighbouring rings' frames turn by
// a small angle, and by no more than the tangent itself turns (a rotation-minimising
// frame adds no twist of its own), and the normals never flip.
TEST(Frames, AdultAnatomyTurnsSmoothlyWithoutTwistOrFlip) {
  const Parameters params = loadParameters(test::asset("params/default.json"));
  const ColonModel model = loadColonModel(test::asset("anatomy/adult.json"), params);
  ColonRings rings;
  TubeOptions options;
  options.samples_per_segment = 10;  // rings 1.5 mm apart
  sampleColonRings(model, model.q_rest, options, rings);
  ASSERT_EQ(rings.frame.size(), static_cast<size_t>((model.n - 1) * 10 + 1));
  double max_turn = 0, max_excess = 0;
  for (size_t i = 0; i + 1 < rings.frame.size(); ++i) {
    const CurveFrame& a = rings.frame[i];
    const CurveFrame& b = rings.frame[i + 1];
    // Orthonormal, right-handed, tangent along the spline.
    EXPECT_NEAR(a.r.norm(), 1.0, 1e-12);
    EXPECT_NEAR(a.r.dot(a.t), 0.0, 1e-12);
    EXPECT_NEAR(a.s.dot(a.t.cross(a.r)), 1.0, 1e-12);
    EXPECT_NEAR(angleBetween(a.t, rings.tangent[i]), 0.0, 1e-9);
    const double turn = frameRotationAngle(a, b);
    const double tangent_turn = angleBetween(a.t, b.t);
    max_turn = std::max(max_turn, turn);
    max_excess = std::max(max_excess, turn - tangent_turn);
    EXPECT_GT(a.r.dot(b.r), std::cos(8 * kPi / 180)) << "normal flipped at ring " << i;
  }
  // The sharpest bend of the adult centreline (hepatic flexure, bend radius ~7 mm) turns
  // the tangent by ~10.5 deg between rings 1.5 mm apart; the frame may turn that much
  // and no more.
  EXPECT_LT(max_turn, 12 * kPi / 180) << "rings 1.5 mm apart turn by more than 12 deg";
  EXPECT_LT(max_excess, 1e-4) << "the frame twists beyond its tangent's turn";
}

// A planar S curve (an inflection in the middle): the Frenet normal flips sign at the
// inflection; the rotation-minimising frame keeps its out-of-plane axis fixed.
TEST(Frames, PlanarInflectionKeepsTheFrame) {
  std::vector<Vec3> x, t;
  for (int i = 0; i <= 200; ++i) {
    const double u = -1.0 + 2.0 * i / 200;
    x.push_back(Vec3(u, 0.3 * std::sin(kPi * u), 0));
    t.push_back(Vec3(1, 0.3 * kPi * std::cos(kPi * u), 0));
  }
  std::vector<CurveFrame> f;
  rotationMinimisingFrames(x, t, Vec3(0, 1, 0), f);  // an in-plane start (projected)
  for (const CurveFrame& c : f) {
    EXPECT_NEAR(std::abs(c.s.z()), 1.0, 1e-9);  // s = t x r stays the plane normal
    EXPECT_NEAR(c.s.z(), f.front().s.z(), 1e-9);
  }
}

// A straight start has no Frenet frame: any perpendicular serves, and the frames along a
// straight line then stay constant.
TEST(Frames, StraightLineFallsBackAndStaysConstant) {
  const Vec3 r0 = initialNormal(Vec3(0, 0, 2), Vec3::Zero());
  EXPECT_NEAR(r0.norm(), 1.0, 1e-12);
  EXPECT_NEAR(r0.z(), 0.0, 1e-12);
  std::vector<Vec3> x, t;
  for (int i = 0; i < 50; ++i) x.push_back(Vec3(0, 0, 0.01 * i)), t.push_back(Vec3(0, 0, 1));
  std::vector<CurveFrame> f;
  rotationMinimisingFrames(x, t, r0, f);
  for (const CurveFrame& c : f) EXPECT_LT((c.r - r0).norm(), 1e-12);
}

// On a circular helix the rotation-minimising frame rotates relative to the Frenet frame
// at the rate of the torsion: after arclength L the angle between them is tau L.
TEST(Frames, HelixRotatesAgainstFrenetByTorsion) {
  const double a = 0.05, b = 0.02;  // radius, pitch / (2 pi) [m]
  const double c = std::sqrt(a * a + b * b), tau = b / (c * c);
  std::vector<Vec3> x, t;
  const int N = 4000;
  const double T = 4 * kPi;
  for (int i = 0; i <= N; ++i) {
    const double th = T * i / N;
    x.push_back(Vec3(a * std::cos(th), a * std::sin(th), b * th));
    t.push_back(Vec3(-a * std::sin(th), a * std::cos(th), b));
  }
  const Vec3 frenet0(-1, 0, 0);  // principal normal at theta = 0 points to the axis
  std::vector<CurveFrame> f;
  rotationMinimisingFrames(x, t, initialNormal(t[0], Vec3(-a, 0, 0)), f);
  EXPECT_LT((f[0].r - frenet0).norm(), 1e-12);
  const double th = T;
  const Vec3 frenet_end(-std::cos(th), -std::sin(th), 0);
  const double expected = std::fmod(tau * c * T, 2 * kPi);  // tau times arclength, mod 2 pi
  const double got = std::acos(std::clamp(f.back().r.dot(frenet_end), -1.0, 1.0));  // in [0, pi]
  EXPECT_NEAR(got, std::min(expected, 2 * kPi - expected), 1e-3);
}

}  // namespace
}  // namespace colosim
