// The loop measure (trainer/telemetry.h, crossingLoopTurns): a crossing in projection
// closes a loop whose turning number is counted; curves that do not cross count 0.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "trainer/telemetry.h"

namespace colosim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// An alpha loop in the x-z plane: the nodal cubic x = t^2, z = t^3 - t (t in [-1.6, 1.6])
// crosses itself at t = +-1, the point (1, 0); scaled to 3 cm, mirrored when sense < 0.
std::vector<Vec3> alpha(int sense) {
  std::vector<Vec3> p;
  for (int i = 0; i <= 64; ++i) {
    const double t = -1.6 + 3.2 * i / 64;
    p.emplace_back(sense * 0.03 * t * t, 0.0, 0.03 * (t * t * t - t));
  }
  return p;
}

TEST(LoopMeasure, AlphaLoopCountsOneTurnWithItsSense) {
  // The sign follows netTurns (anticlockwise seen from the tip of the normal).
  for (int sense : {1, -1}) {
    const std::vector<Vec3> p = alpha(sense);
    const double turns = crossingLoopTurns(p, Vec3(0, 1, 0));
    EXPECT_DOUBLE_EQ(std::abs(turns), 1.0) << "sense " << sense;
    EXPECT_GT(turns * netTurns(p, Vec3(0, 1, 0)), 0.0) << "same sign as the net turning";
    EXPECT_DOUBLE_EQ(crossingLoopTurns(p, Vec3(0, -1, 0)), -turns) << "seen from the other side";
  }
}

TEST(LoopMeasure, OpenCurvesDoNotCount) {
  // The same circle stopped short of closing: 0.9 turn of net turning, no crossing.
  std::vector<Vec3> open;
  for (int i = 0; i <= 64; ++i) {
    const double a = 0.9 * 2 * kPi * i / 64;
    open.emplace_back(0.03 * (1 - std::cos(a)), 0.0, 0.03 * std::sin(a));
  }
  EXPECT_NEAR(std::abs(netTurns(open, Vec3(0, 1, 0))), 0.9, 0.03);
  EXPECT_EQ(crossingLoopTurns(open, Vec3(0, 1, 0)), 0.0);
  // An S (an N loop's shape) and a straight line.
  std::vector<Vec3> s_shape, line;
  for (int i = 0; i <= 64; ++i) {
    const double a = kPi * i / 32;
    s_shape.emplace_back(0.02 * std::sin(a), 0.0, 0.01 * i);
    line.emplace_back(0.001 * i, 0.002 * i, 0.01 * i);
  }
  EXPECT_EQ(crossingLoopTurns(s_shape, Vec3(0, 1, 0)), 0.0);
  EXPECT_EQ(crossingLoopTurns(line, Vec3(0, 1, 0)), 0.0);
  // A loop that crosses only in depth (along the normal) but not in projection: a helix
  // seen from the side is an S, not a loop.
  std::vector<Vec3> helix;
  for (int i = 0; i <= 64; ++i) {
    const double a = 2 * kPi * i / 64;
    helix.emplace_back(0.03 * std::cos(a), 0.03 * std::sin(a), 0.004 * i);
  }
  EXPECT_EQ(crossingLoopTurns(helix, Vec3(0, 1, 0)), 0.0);
}

TEST(LoopMeasure, TwoTurnsOfASpiralCountTwo) {
  // A spiral wound twice with a tail crossing both turns: the largest loop turns twice.
  std::vector<Vec3> p;
  for (int i = 0; i <= 128; ++i) {
    const double a = 2 * 2 * kPi * i / 128;
    const double r = 0.02 + 0.01 * i / 128.0;
    p.emplace_back(r * std::cos(a), 0.0, r * std::sin(a));
  }
  p.emplace_back(0.0, 0.0, 0.0015);  // back across both turns, between their corners
  EXPECT_DOUBLE_EQ(std::abs(crossingLoopTurns(p, Vec3(0, 1, 0))), 2.0);
}

}  // namespace
}  // namespace colosim
