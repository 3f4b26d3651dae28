// A progress bar with the time left on stderr for long headless work (run, replay and
// their videos, score, identify), drawn only when stderr is a terminal: logs, pipes and
// --json output stay clean.
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
  /// The bar's text for `done` out of `total`, e.g. "score [#####     ]  50%", and with
  /// seconds_left >= 0 the time left, e.g. "score [#####     ]  50%  1 min 05 s left".
  static std::string render(const std::string& label, long done, long total, int width = 30,
                            double seconds_left = -1);
  /// "12 s", "1 min 05 s", "2 h 03 min" (whole seconds, rounded up).
  static std::string formatDuration(double seconds);
  /// The time left at a constant rate: elapsed (total - done) / done [s]; -1 (unknown)
  /// before anything is done or in the first second.
  static double secondsLeft(double elapsed_s, long done, long total);

 private:
  std::string label_;
  long total_;
  bool enabled_;
  std::FILE* out_;
  bool finished_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_draw_{};
  size_t drawn_width_ = 0;  ///< characters of the last line drawn (a shorter one clears the rest)
};

}  // namespace colosim
