#include "trainer/progress.h"

#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "fixture.h"

namespace colosim {
namespace {

TEST(Progress, RendersTheFractionDone) {
  EXPECT_EQ(ProgressBar::render("score", 0, 10, 10), "score [          ]   0%");
  EXPECT_EQ(ProgressBar::render("score", 5, 10, 10), "score [#####     ]  50%");
  EXPECT_EQ(ProgressBar::render("score", 10, 10, 10), "score [##########] 100%");
  EXPECT_EQ(ProgressBar::render("score", 12, 10, 10), "score [##########] 100%");
}

TEST(Progress, ShowsTheTimeLeft) {
  EXPECT_EQ(ProgressBar::render("run", 5, 10, 10, 65.2), "run [#####     ]  50%  1 min 06 s left");
  EXPECT_EQ(ProgressBar::formatDuration(12.0), "12 s");
  EXPECT_EQ(ProgressBar::formatDuration(0.2), "1 s");
  EXPECT_EQ(ProgressBar::formatDuration(3725), "1 h 02 min");
  // At a constant rate: 20 s for a quarter, 60 s for the rest; unknown before anything is
  // done and in the first second (no wild guesses).
  EXPECT_DOUBLE_EQ(ProgressBar::secondsLeft(20.0, 25, 100), 60.0);
  EXPECT_LT(ProgressBar::secondsLeft(20.0, 0, 100), 0.0);
  EXPECT_LT(ProgressBar::secondsLeft(0.5, 50, 100), 0.0);
}

// The bar a terminal gets, drawn into a file: carriage returns, then the final line with
// the elapsed time.
TEST(Progress, EnabledDrawsTheBarAndEndsTheLine) {
  std::FILE* f = std::tmpfile();
  {
    ProgressBar bar("score", 10, true, f);
    bar.update(5);
    bar.finish();
  }
  std::rewind(f);
  char buf[512] = {0};
  const size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  const std::string out(buf, n);
  EXPECT_NE(out.find("\rscore [###############               ]  50%"), std::string::npos) << out;
  EXPECT_NE(out.find("\rscore [##############################] 100%  1 s"), std::string::npos) << out;
  EXPECT_EQ(out.back(), '\n');
  std::fclose(f);
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

// Through the command, on a pseudo-terminal (util-linux `script`): the bar and its final
// line with the elapsed time on a terminal; with --json, the JSON alone.
TEST(Progress, ATerminalGetsTheBarAndJsonGetsNothingExtra) {
  if (test::runCommand("command -v script >/dev/null").code != 0) GTEST_SKIP() << "no script(1)";
  const std::string run = std::string(COLOSIM_EXE) + " run sigmoid_untwist --duration 0.3";
  const test::CommandResult tty = test::runCommand("script -qec '" + run + "' /dev/null");
  ASSERT_EQ(tty.code, 0) << tty.out;
  EXPECT_NE(tty.out.find("\rrun sigmoid_untwist [##############################] 100%  "), std::string::npos)
      << tty.out;
  const test::CommandResult json = test::runCommand("script -qec '" + run + " --score --json' /dev/null");
  ASSERT_EQ(json.code, 0) << json.out;
  EXPECT_EQ(json.out.find("[#"), std::string::npos) << json.out;
  EXPECT_EQ(json.out.find("100%"), std::string::npos) << json.out;
  // Not a terminal: nothing on stderr either.
  const test::CommandResult pipe = test::runCommand(run + " 2>&1 >/dev/null");
  EXPECT_EQ(pipe.out.find("100%"), std::string::npos) << pipe.out;
}

}  // namespace
}  // namespace colosim
