#include "app/options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/input_error.h"
#include "trainer/scene_drawing.h"

namespace colosim::app {

SizePx parseSize(const std::string& text, int min_px) {
  SizePx s;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &s.width, &s.height, &extra) != 2 || s.width < min_px ||
      s.height < min_px || s.width > 8192 || s.height > 8192)
    throw InputError("--size: expected WxH in pixels (" + std::to_string(min_px) + "..8192), got '" + text + "'");
  return s;
}

void checkFramesDir(const std::string& dir) {
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_empty(dir, ec))
    throw InputError(dir + ": exists and is not empty (frames never overwrite files)");
}

void addFrames(RunHooks& hooks, const std::string& dir, const std::string& view, const SizePx& size, double fps,
               double dt_s) {
  std::filesystem::create_directories(dir);
  hooks.on_frame = makeFrameWriter(dir, view, size.width, size.height);
  hooks.frame_every_steps = std::max(1L, std::lround(1.0 / (fps * dt_s)));
}

void printScores(const nlohmann::json& scores) {
  std::printf("  scores:\n");
  for (auto it = scores.begin(); it != scores.end(); ++it) {
    if (it.value().is_object() || it.value().is_array()) continue;
    std::printf("    %-34s %s\n", it.key().c_str(), it.value().dump().c_str());
  }
}

void printTensionLaw(const TensionLaw& law, const std::string& from) {
  std::printf("  tension law          %s from %s:", law.name().c_str(), from.c_str());
  for (const LawParameter& p : law.parameters()) std::printf(" %s = %.4g %s;", p.name.c_str(), p.value, p.unit.c_str());
  std::printf("\n");
}

}  // namespace colosim::app
