// A crash report for the `colosim` command: on a fatal signal (SIGSEGV, SIGBUS, SIGFPE,
// SIGILL) the process writes which signal, in which thread, and a backtrace to stderr, then
// dies by the same signal (exit status 128 + N kept for the scripts and tests that read it).
// A crash in the trainer window once showed only "exited with 139" in CI; the next one
// names its frames. Not installed under the sanitizers, whose own handlers report more.
#pragma once

namespace colosim::app {

/// Installs the handlers (idempotent). Call from main before any other thread starts.
void installCrashReport();

}  // namespace colosim::app
