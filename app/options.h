// What several subcommands share: option values parsed one way, result blocks printed one way.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/tension_law.h"
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
/// Writes frames of `view` at `size` into `dir` (created) every 1 / fps simulated seconds
/// of a simulation stepping dt_s: the frame hooks of a run or replay.
void addFrames(RunHooks& hooks, const std::string& dir, const std::string& view, const SizePx& size, double fps,
               double dt_s);

/// "  scores:" and one line per scalar score (run --score, train).
void printScores(const nlohmann::json& scores);
/// "  tension law          NAME from FILE: p = v unit; ..." (run, run settle).
void printTensionLaw(const TensionLaw& law, const std::string& from);

}  // namespace colosim::app
