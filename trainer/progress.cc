#include "trainer/progress.h"

#include <algorithm>

#include <unistd.h>

namespace colosim {

bool stderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(std::string label, long total, bool enabled, std::FILE* out)
    : label_(std::move(label)), total_(total), enabled_(enabled), out_(out) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && !finished_) std::fputc('\n', out_);
}

std::string ProgressBar::render(const std::string& label, long done, long total, int width) {
  const double f = total > 0 ? std::clamp(static_cast<double>(done) / total, 0.0, 1.0) : 1.0;
  const int filled = static_cast<int>(f * width + 1e-9);
  char pct[8];
  std::snprintf(pct, sizeof pct, "%3d%%", static_cast<int>(100 * f + 1e-9));
  return label + " [" + std::string(filled, '#') + std::string(width - filled, ' ') + "] " + pct;
}

void ProgressBar::update(long done) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  std::fprintf(out_, "\r%s", render(label_, done, total_).c_str());
  std::fflush(out_);
}

void ProgressBar::finish() {
  if (!enabled_ || finished_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  std::fprintf(out_, "\r%s\n", render(label_, total_, total_).c_str());
  std::fflush(out_);
  finished_ = true;
}

}  // namespace colosim
