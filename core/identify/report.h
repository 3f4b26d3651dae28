// What `colosim identify` prints and writes: the result as JSON, and a report folder
// with PNG plots made by gnuplot (Debian's gnuplot-nox, pngcairo terminal) and the text
// of the diagnosis.
#pragma once

#include <string>
#include <vector>

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

/// A data file of a report folder: its name in the folder and its bytes.
struct ReportFile {
  std::string name;
  std::string text;
};

/// Writes a gnuplot report folder and runs it (the tension report above and the organ report
/// of organ/report.h): creates dir/ if missing, writes the data files, the script as
/// report.gp, diagnosis.txt and result as identify.json, then runs `gnuplot report.gp` in
/// dir/ (its output in gnuplot.log). Throws std::runtime_error when the folder or a file
/// cannot be written or gnuplot fails.
void writeGnuplotReport(const std::string& dir, const std::vector<ReportFile>& data, const std::string& script,
                        const std::string& diagnosis, const nlohmann::json& result);

}  // namespace colosim
