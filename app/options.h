// What several subcommands share: option values parsed one way, result blocks printed one way.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "core/tension_law.h"
#include "trainer/frame_export.h"
#include "trainer/replay.h"

namespace colosim::app {

struct SizePx {
  int width = 0, height = 0;  ///< [px]
};
/// --size WxH: InputError "--size: expected WxH in pixels (MIN..8192), got '...'" unless
/// both are in [min_px, 8192].
SizePx parseSize(const std::string& text, int min_px);

/// --frames DIR: InputError unless DIR is new or empty (frames never overwrite files).
void checkFramesDir(const std::string& dir);
/// --video FILE: InputError unless FILE is new (a video never overwrites a file) and the
/// image (twice the width for view "both") has an even width and height.
void checkVideoFile(const std::string& path, const std::string& view, const SizePx& size);
/// Frames of `view` at `size` every 1 / fps simulated seconds of a simulation stepping
/// dt_s, as PNG files into `frames_dir` (created; "" for none) and/or a video (`video`, ""
/// for none) playing at that rate: the frame hook of a run or replay. Call finish() on the
/// result after the run.
std::shared_ptr<FrameExporter> addFrameExport(RunHooks& hooks, const std::string& frames_dir,
                                              const std::string& video, const std::string& view, const SizePx& size,
                                              double fps, double dt_s);

/// "  scores:" and one line per scalar score (run --score, train).
void printScores(const nlohmann::json& scores);
/// "  tension law          NAME from FILE: p = v unit; ..." (run, run settle).
void printTensionLaw(const TensionLaw& law, const std::string& from);

}  // namespace colosim::app
