#include "app/crash_report.h"

#include <execinfo.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cstring>
#include <initializer_list>

namespace colosim::app {
namespace {

// Only async-signal-safe calls in the handler: write(2), prctl(2), and backtrace(), whose
// one allocation (loading libgcc's unwinder) is done at installation.
void say(const char* s) {
  for (size_t n = std::strlen(s); n > 0;) {
    const ssize_t w = ::write(STDERR_FILENO, s, n);
    if (w <= 0) return;
    s += w, n -= static_cast<size_t>(w);
  }
}

void sayNumber(int v) {
  char digits[12];
  int k = sizeof digits - 1;
  digits[k] = '\0';
  do digits[--k] = static_cast<char>('0' + v % 10);
  while ((v /= 10) > 0 && k > 0);
  say(digits + k);
}

void onFatalSignal(int sig) {
  say("colosim: fatal signal ");
  sayNumber(sig);
  say(" (");
  say(sig == SIGSEGV ? "SIGSEGV" : sig == SIGBUS ? "SIGBUS" : sig == SIGFPE ? "SIGFPE" : "SIGILL");
  say(") in thread '");
  char name[17] = {};
  if (::prctl(PR_GET_NAME, name, 0, 0, 0) == 0) say(name);
  say("'; backtrace (addr2line -f -C -e BINARY OFFSET names a frame):\n");
  void* frames[64];
  const int n = ::backtrace(frames, 64);
  ::backtrace_symbols_fd(frames, n, STDERR_FILENO);
  // Die by the same signal: SA_RESETHAND restored the default action on entry, and the
  // signal raised again is delivered when the handler returns.
  ::raise(sig);
}

}  // namespace

void installCrashReport() {
#if defined(__SANITIZE_ADDRESS__) || defined(COLOSIM_SANITIZED)
  return;
#else
  static bool installed = false;
  if (installed) return;
  installed = true;
  void* warm[1];
  ::backtrace(warm, 1);  // loads the unwinder now, not inside the handler
  // An alternate stack, so that a stack overflow of the main thread is reported too.
  static char alt_stack[64 * 1024];
  stack_t ss{};
  ss.ss_sp = alt_stack;
  ss.ss_size = sizeof alt_stack;
  ::sigaltstack(&ss, nullptr);
  struct sigaction sa {};
  sa.sa_handler = onFatalSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_ONSTACK | SA_RESETHAND;
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL}) ::sigaction(sig, &sa, nullptr);
#endif
}

}  // namespace colosim::app
