// What `colosim identify` prints and writes for a tension test: the result as JSON, and a
// report folder (identify/report.h) with PNG plots and the text of the diagnosis.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "identify/report.h"
#include "identify/tension/identify.h"

namespace colosim {

/// The force's decay at held strain (HoldDecay) as a JSON object.
nlohmann::json holdDecayJson(const HoldDecay& h);

/// The result as one JSON object: effects, baseline, extended, gain, unexplained, evidence
/// (docs/identification.md lists every key).
nlohmann::json identifyJson(const TensionTest& test, const IdentifyResult& r);

/// Writes dir/ (created if missing): force_time.png, force_elongation.png, residuals.png,
/// diagnosis.txt, identify.json, and the gnuplot script and data behind the plots.
/// Throws std::runtime_error when a file cannot be written or gnuplot fails.
void writeIdentifyReport(const std::string& dir, const TensionTest& test, const IdentifyResult& r);

}  // namespace colosim
