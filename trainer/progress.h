// A progress bar on stderr for long headless work, drawn only when stderr is a terminal
// (logs and pipes stay clean).
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace colosim {

/// True when stderr is a terminal.
bool stderrIsTerminal();

class ProgressBar {
 public:
  /// `enabled` false draws nothing (use stderrIsTerminal()); `out` is where it draws.
  ProgressBar(std::string label, long total, bool enabled, std::FILE* out = stderr);
  ~ProgressBar();
  /// Sets the amount done (thread-safe); redraws at most every 100 ms.
  void update(long done);
  /// Draws 100 % and ends the line.
  void finish();
  /// The bar's text for `done` out of `total`, e.g. "score [#####     ]  50%" (for tests).
  static std::string render(const std::string& label, long done, long total, int width = 30);

 private:
  std::string label_;
  long total_;
  bool enabled_;
  std::FILE* out_;
  bool finished_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace colosim
