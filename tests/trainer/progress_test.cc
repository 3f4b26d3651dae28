#include "trainer/progress.h"

#include <cstdio>

#include <gtest/gtest.h>

namespace colosim {
namespace {

TEST(Progress, RendersTheFractionDone) {
  EXPECT_EQ(ProgressBar::render("score", 0, 10, 10), "score [          ]   0%");
  EXPECT_EQ(ProgressBar::render("score", 5, 10, 10), "score [#####     ]  50%");
  EXPECT_EQ(ProgressBar::render("score", 10, 10, 10), "score [##########] 100%");
  EXPECT_EQ(ProgressBar::render("score", 12, 10, 10), "score [##########] 100%");
}

TEST(Progress, DisabledDrawsNothing) {
  std::FILE* f = std::tmpfile();
  {
    ProgressBar bar("x", 10, false, f);
    bar.update(5);
    bar.finish();
  }
  EXPECT_EQ(std::ftell(f), 0L);
  std::fclose(f);
}

}  // namespace
}  // namespace colosim
