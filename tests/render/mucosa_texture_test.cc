#include "render/mucosa_texture.h"

#include <gtest/gtest.h>

#include <cmath>

namespace colosim {
namespace {

double columnJump(const Image& img, int x0, int x1) {
  double sum = 0;
  for (int y = 0; y < img.height; ++y)
    for (int c = 0; c < 3; ++c) sum += std::abs(img.at(x0, y)[c] - img.at(x1, y)[c]);
  return sum / img.height;
}

double rowJump(const Image& img, int y0, int y1) {
  double sum = 0;
  for (int x = 0; x < img.width; ++x)
    for (int c = 0; c < 3; ++c) sum += std::abs(img.at(x, y0)[c] - img.at(x, y1)[c]);
  return sum / img.width;
}

TEST(MucosaTexture, DeterministicForASeedDifferentForAnother) {
  const Image a = makeMucosaTexture(), b = makeMucosaTexture();
  EXPECT_EQ(a.rgba, b.rgba);
  MucosaOptions other;
  other.seed = 7;
  EXPECT_NE(a.rgba, makeMucosaTexture(other).rgba);
}

// The seam around the colon (u = 0 meets u = 1) and the repeat along it must not show:
// the jump across the wrap is like the jump between any two neighbouring columns.
TEST(MucosaTexture, TilesWithoutSeams) {
  const Image img = makeMucosaTexture();
  const int N = img.width;
  double inner_cols = 0, inner_rows = 0;
  for (int k = 1; k < N; ++k) inner_cols += columnJump(img, k - 1, k), inner_rows += rowJump(img, k - 1, k);
  inner_cols /= N - 1;
  inner_rows /= N - 1;
  EXPECT_LT(columnJump(img, N - 1, 0), 2.5 * inner_cols);
  EXPECT_LT(rowJump(img, N - 1, 0), 2.5 * inner_rows);
}

// Pink mucosa with darker red vessels covering a modest part of the wall.
TEST(MucosaTexture, PinkWallWithVessels) {
  const Image img = makeMucosaTexture();
  double r = 0, g = 0, b = 0;
  int vessel_px = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const uint8_t* p = img.at(x, y);
      r += p[0], g += p[1], b += p[2];
      EXPECT_EQ(p[3], 255);
      if (p[1] < 90 && p[0] > p[1] + 60) ++vessel_px;  // dark red
    }
  }
  const double n = static_cast<double>(img.width) * img.height;
  EXPECT_GT(r / n, 170);
  EXPECT_GT(r / n, g / n + 60);
  EXPECT_GT(r / n, b / n + 60);
  EXPECT_GT(vessel_px / n, 0.01);
  EXPECT_LT(vessel_px / n, 0.25);
}

}  // namespace
}  // namespace colosim
