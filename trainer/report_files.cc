#include "trainer/report_files.h"

#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace colosim {

namespace {

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

void writeReportText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error(p.string() + ": cannot write the file");
}

void runReportGnuplot(const std::filesystem::path& dir) {
  const std::string cmd = "cd " + shellQuote(dir.string()) + " && gnuplot report.gp > gnuplot.log 2>&1";
  if (std::system(cmd.c_str()) != 0)
    throw std::runtime_error("gnuplot failed (see " + (dir / "gnuplot.log").string() + ")");
}

}  // namespace colosim
