// The files of a report folder (colosim identify --report, colosim score --report): text
// written whole, and the folder's gnuplot script run in it.
#pragma once

#include <filesystem>
#include <string>

namespace colosim {

/// Writes `text` into `path` (replacing it); throws std::runtime_error naming the file.
void writeReportText(const std::filesystem::path& path, const std::string& text);

/// Runs gnuplot on `dir`/report.gp in `dir`, its messages into `dir`/gnuplot.log; throws
/// std::runtime_error naming the log when gnuplot fails.
void runReportGnuplot(const std::filesystem::path& dir);

}  // namespace colosim
