#include "app/options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/input_error.h"

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

void checkVideoFile(const std::string& path, const std::string& view, const SizePx& size) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) throw InputError(path + ": exists (--video never overwrites a file)");
  const int width = view == "both" ? 2 * size.width : size.width;
  if (width % 2 != 0 || size.height % 2 != 0)
    throw InputError("--size " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                     ": a video needs an even width and height");
}

std::shared_ptr<FrameExporter> addFrameExport(RunHooks& hooks, const std::string& frames_dir,
                                              const std::string& video, const std::string& view, const SizePx& size,
                                              double fps, double dt_s) {
  if (frames_dir.empty() && video.empty()) return nullptr;
  if (!frames_dir.empty()) std::filesystem::create_directories(frames_dir);
  hooks.frame_every_steps = std::max(1L, std::lround(1.0 / (fps * dt_s)));
  FrameExportOptions o;
  o.frames_dir = frames_dir;
  o.video_path = video;
  o.view = view;
  o.width_px = size.width;
  o.height_px = size.height;
  o.fps = 1.0 / (hooks.frame_every_steps * dt_s);  // real time: one frame per frame interval
  auto exporter = std::make_shared<FrameExporter>(o);
  hooks.on_frame = [exporter](const Simulation& sim, long steps_done) { (*exporter)(sim, steps_done); };
  return exporter;
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
