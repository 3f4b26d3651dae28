// What `colosim identify` prints and writes: the result as JSON, and a report folder
// with PNG plots made by gnuplot (Debian's gnuplot-nox, pngcairo terminal) and the text
// of the diagnosis.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/identify/identify.h"

namespace colosim {

/// The result as one JSON object: effects, baseline, extended, gain, unexplained, evidence
/// (docs/identification.md lists every key).
nlohmann::json identifyJson(const TensionTest& test, const IdentifyResult& r);

/// Writes dir/ (created if missing): force_time.png, force_elongation.png, residuals.png,
/// diagnosis.txt, identify.json, and the gnuplot script and data behind the plots.
/// Throws std::runtime_error when a file cannot be written or gnuplot fails.
void writeIdentifyReport(const std::string& dir, const TensionTest& test, const IdentifyResult& r);

}  // namespace colosim
