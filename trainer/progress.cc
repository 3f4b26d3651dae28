#include "trainer/progress.h"

#include <algorithm>
#include <cmath>

#include <unistd.h>

namespace colosim {

bool stderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::string label, long total, bool enabled, std::FILE* out)
    : label_(std::move(label)), total_(total), enabled_(enabled), out_(out) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && !finished_) std::fputc('\n', out_);
}

std::string ProgressBar::formatDuration(double seconds) {
  const long s = static_cast<long>(std::ceil(std::max(0.0, seconds) - 1e-9));
  char buf[48];
  if (s < 60) std::snprintf(buf, sizeof buf, "%ld s", s);
  else if (s < 3600) std::snprintf(buf, sizeof buf, "%ld min %02ld s", s / 60, s % 60);
  else std::snprintf(buf, sizeof buf, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return buf;
}

double ProgressBar::secondsLeft(double elapsed_s, long done, long total) {
  if (done <= 0 || elapsed_s < 1.0) return -1;
  return elapsed_s * static_cast<double>(std::max(0L, total - done)) / static_cast<double>(done);
}

std::string ProgressBar::render(const std::string& label, long done, long total, int width, double seconds_left) {
  const double f = total > 0 ? std::clamp(static_cast<double>(done) / total, 0.0, 1.0) : 1.0;
  const int filled = static_cast<int>(f * width + 1e-9);
  char pct[8];
  std::snprintf(pct, sizeof pct, "%3d%%", static_cast<int>(100 * f + 1e-9));
  std::string s = label + " [" + std::string(filled, '#') + std::string(width - filled, ' ') + "] " + pct;
  if (seconds_left >= 0) s += "  " + formatDuration(seconds_left) + " left";
  return s;
}

void ProgressBar::update(long done) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double elapsed_s = std::chrono::duration<double>(now - start_).count();
  const std::string line = render(label_, done, total_, 30, secondsLeft(elapsed_s, done, total_));
  // Spaces over what a longer previous line left (the time left shrinks).
  std::fprintf(out_, "\r%s%s", line.c_str(), std::string(drawn_width_ > line.size() ? drawn_width_ - line.size() : 0, ' ').c_str());
  drawn_width_ = line.size();
  std::fflush(out_);
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string line = render(label_, total_, total_) + "  " + formatDuration(elapsed_s);
  std::fprintf(out_, "\r%s%s\n", line.c_str(), std::string(drawn_width_ > line.size() ? drawn_width_ - line.size() : 0, ' ').c_str());
  std::fflush(out_);
  finished_ = true;
}

}  // namespace colosim
