// The `colosim` command's crash report (app/crash_report.h): a fatal signal is named with its
// thread and a backtrace on stderr, and the process still dies by that signal.
#include "app/crash_report.h"

#include <csignal>

#include <gtest/gtest.h>

namespace colosim::app {
namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(COLOSIM_SANITIZED)
TEST(CrashReport, IsLeftToTheSanitizers) { GTEST_SKIP() << "the sanitizers' handlers report crashes"; }
#else
TEST(CrashReport, NamesARaisedSignalAndDiesByIt) {
  EXPECT_EXIT(
      {
        installCrashReport();
        std::raise(SIGSEGV);
      },
      ::testing::KilledBySignal(SIGSEGV), "colosim: fatal signal 11 \\(SIGSEGV\\) in thread '.*'; backtrace");
}

TEST(CrashReport, ReportsARealFaultWithItsFrames) {
  EXPECT_EXIT(
      {
        installCrashReport();
        volatile int* p = nullptr;
        *p = 1;
      },
      ::testing::KilledBySignal(SIGSEGV), "fatal signal 11 \\(SIGSEGV\\)(.|\n)*crash_report_tests");
}

TEST(CrashReport, NamesAnArithmeticFault) {
  EXPECT_EXIT(
      {
        installCrashReport();
        std::raise(SIGFPE);
      },
      ::testing::KilledBySignal(SIGFPE), "fatal signal 8 \\(SIGFPE\\)");
}
#endif

}  // namespace
}  // namespace colosim::app
