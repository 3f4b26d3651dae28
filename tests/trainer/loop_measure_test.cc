// The loop measure (trainer/telemetry.h, crossingLoopTurns): a crossing in projection
// closes a loop whose turning number is counted; curves that do not cross count 0.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "trainer/telemetry.h"
#include "core/numbers.h"

namespace colosim {
namespace {

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


// --- The 3-D loop measure (closedWrithe) ---

// The alpha loop above lifted out of its plane: y = lift * t, so the limbs pass each other
// 2 * lift apart at the crossing.
std::vector<Vec3> liftedAlpha(int sense, double lift_m) {
  std::vector<Vec3> p = alpha(sense);
  for (int i = 0; i <= 64; ++i) p[i].y() = lift_m * (-1.6 + 3.2 * i / 64);
  return p;
}

// Brute force: the Gauss double integral (1 / 4 pi) sum over ordered pairs of distinct edges
// of int int (t1 x t2) . (r1 - r2) / |r1 - r2|^3, with `nodes`-point Gauss-Legendre on each
// edge of the closed polygon (adjacent edges are coplanar and contribute exactly 0).
double gaussIntegralWrithe(const std::vector<Vec3>& open, int nodes) {
  std::vector<Vec3> p = open;
  const int m = static_cast<int>(p.size());
  // Nodes and weights on [0, 1] by Newton on the Legendre polynomial.
  std::vector<double> x(nodes), w(nodes);
  for (int i = 0; i < nodes; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (nodes + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= nodes; ++k) {
        const double pk = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = pk;
      }
      dp = nodes * (z * p1 - p0) / (z * z - 1);
      z -= p1 / dp;
    }
    x[i] = 0.5 * (1 - z);
    w[i] = 1.0 / ((1 - z * z) * dp * dp);
  }
  double sum = 0;
  for (int i = 0; i < m; ++i) {
    const Vec3 a0 = p[i], a = p[(i + 1) % m] - a0;
    for (int j = 0; j < m; ++j) {
      if (j == i || j == (i + 1) % m || i == (j + 1) % m) continue;
      const Vec3 b0 = p[j], b = p[(j + 1) % m] - b0;
      for (int u = 0; u < nodes; ++u)
        for (int v = 0; v < nodes; ++v) {
          const Vec3 r = (a0 + x[u] * a) - (b0 + x[v] * b);
          sum += w[u] * w[v] * a.cross(b).dot(r) / std::pow(r.norm(), 3);
        }
    }
  }
  return sum / (4 * kPi);
}

// The pair formula as Klenin & Langowski write it (method 1a: four face normals and four
// arcsines per pair of edges), for the closed polygon of `open`.
double kleninLangowskiWrithe(const std::vector<Vec3>& p) {
  const int m = static_cast<int>(p.size());
  auto unit = [](const Vec3& a) -> Vec3 {
    const double l = a.norm();
    return l > 0 ? Vec3(a / l) : Vec3::Zero();
  };
  auto asinClamped = [](double x) { return std::asin(std::clamp(x, -1.0, 1.0)); };
  double sum = 0.0;
  for (int i = 0; i < m; ++i)
    for (int j = i + 2; j < m; ++j) {
      if (i == 0 && j == m - 1) continue;
      const Vec3 &p1 = p[i], &p2 = p[(i + 1) % m], &p3 = p[j], &p4 = p[(j + 1) % m];
      const Vec3 r13 = p3 - p1, r14 = p4 - p1, r23 = p3 - p2, r24 = p4 - p2;
      const Vec3 n1 = unit(r13.cross(r14)), n2 = unit(r14.cross(r24));
      const Vec3 n3 = unit(r24.cross(r23)), n4 = unit(r23.cross(r13));
      const double omega = asinClamped(n1.dot(n2)) + asinClamped(n2.dot(n3)) + asinClamped(n3.dot(n4)) +
                           asinClamped(n4.dot(n1));
      const double orient = (p4 - p3).cross(p2 - p1).dot(r13);
      sum += orient > 0 ? omega : (orient < 0 ? -omega : 0.0);
    }
  return sum / (2.0 * kPi);
}

// The measure's two triangles per pair of edges against the four arcsines, on random closed
// polygons (knotted and not) and on the lifted alpha loops.
TEST(LoopWrithe, AgreesWithKleninAndLangowskisPairFormula) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 0.03);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec3> p;
    for (int i = 0; i < 8 + 3 * trial; ++i) p.emplace_back(g(rng), g(rng), g(rng));
    const double want = kleninLangowskiWrithe(p);
    EXPECT_NEAR(closedWrithe(p), want, 1e-11 * std::max(1.0, std::abs(want))) << "trial " << trial;
  }
  for (double lift_m : {0.004, 0.00025}) {
    const std::vector<Vec3> a = liftedAlpha(1, lift_m);
    EXPECT_NEAR(closedWrithe(a), kleninLangowskiWrithe(a), 1e-11) << lift_m;
  }
}

TEST(LoopWrithe, PlanarCurvesHaveNone) {
  EXPECT_NEAR(closedWrithe(alpha(1)), 0.0, 1e-12) << "a planar alpha loop";
  std::vector<Vec3> bend;
  for (int i = 0; i <= 32; ++i) bend.emplace_back(0.1 * std::cos(kPi * i / 32), 0.0, 0.1 * std::sin(kPi * i / 32));
  EXPECT_NEAR(closedWrithe(bend), 0.0, 1e-12) << "a half circle";
}

TEST(LoopWrithe, AnAlphaLoopWrithesAboutOneTurnWithItsHandedness) {
  // As the loop flattens, its writhe tends to the sign of its one crossing.
  double previous_error = 1.0;
  for (double lift_m : {0.004, 0.001, 0.00025}) {
    const double wr = closedWrithe(liftedAlpha(1, lift_m));
    EXPECT_LT(std::abs(std::abs(wr) - 1.0), previous_error) << "converges, lift " << lift_m;
    previous_error = std::abs(std::abs(wr) - 1.0);
    // Its mirror images have the opposite handedness.
    EXPECT_NEAR(closedWrithe(liftedAlpha(-1, lift_m)), -wr, 1e-12);
    EXPECT_NEAR(closedWrithe(liftedAlpha(1, -lift_m)), -wr, 1e-12);
  }
  EXPECT_LT(previous_error, 0.05);
  // Which limb lies in front decides the sign; the coronal crossing number cannot tell.
  EXPECT_DOUBLE_EQ(std::abs(crossingLoopTurns(liftedAlpha(1, 0.001), Vec3(0, 1, 0))),
                   std::abs(crossingLoopTurns(liftedAlpha(1, -0.001), Vec3(0, 1, 0))));
}

TEST(LoopWrithe, SignIsTheCrossingsInKnotTheory) {
  // The lifted alpha loop crosses itself at t = -1 and t = +1; seen from +y the limb with
  // the larger y (t = +lift) lies over the other. Knot theory's sign of a crossing: +1 when
  // (over tangent x under tangent) points at the viewer (a right-handed crossing).
  for (int sense : {1, -1})
    for (double lift_m : {0.001, -0.001}) {
      auto tangent = [&](double t) { return Vec3(sense * 0.06 * t, lift_m, 0.03 * (3 * t * t - 1)); };
      const double t_over = lift_m > 0 ? 1.0 : -1.0;
      const double sign = tangent(t_over).cross(tangent(-t_over)).y() > 0 ? 1.0 : -1.0;
      EXPECT_GT(closedWrithe(liftedAlpha(sense, lift_m)) * sign, 0.9) << "sense " << sense << ", lift " << lift_m;
    }
}

TEST(LoopWrithe, InvariantUnderRigidMotionAndScale) {
  const std::vector<Vec3> p = liftedAlpha(1, 0.003);
  const double wr = closedWrithe(p);
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<Vec3> moved;
  for (const Vec3& x : p) moved.push_back(2.5 * (R * x) + Vec3(0.1, -0.2, 0.3));
  EXPECT_NEAR(closedWrithe(moved), wr, 1e-12);
}

TEST(LoopWrithe, AgreesWithTheGaussIntegralByQuadrature) {
  // A trefoil knot (writhe about 3.4 for this embedding) and the lifted alpha loop, each
  // polygon's writhe against its Gauss integral summed by brute force.
  std::vector<Vec3> trefoil;
  for (int i = 0; i < 48; ++i) {
    const double s = 2 * kPi * i / 48;
    trefoil.emplace_back(std::sin(s) + 2 * std::sin(2 * s), std::cos(s) - 2 * std::cos(2 * s), -std::sin(3 * s));
  }
  for (const std::vector<Vec3>& p : {trefoil, liftedAlpha(1, 0.003)}) {
    const double exact = closedWrithe(p);
    EXPECT_NEAR(gaussIntegralWrithe(p, 24), exact, 2e-3 * std::max(1.0, std::abs(exact)));
  }
}

}  // namespace
}  // namespace colosim
