// The confusion table of a hidden-effect trial tool (identify_tension_trials, organ_trials)
// as a gnuplot heat map, for identify/report.h writeGnuplotReport: the data file
// (confusion.dat: row, column, fraction, count) and the script that draws confusion.png.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace colosim {

struct ConfusionPlot {
  std::string data;    ///< confusion.dat
  std::string script;  ///< the gnuplot script
};

/// counts[i][k]: cases of hidden class rows[i] named as cols[k], each row out of per_row.
inline ConfusionPlot confusionPlot(const std::vector<std::string>& rows, const std::vector<std::string>& cols,
                                   const std::vector<std::vector<int>>& counts, int per_row,
                                   const std::string& title, const std::string& xlabel) {
  ConfusionPlot p;
  p.data = "# hidden named fraction count\n";
  char line[128];
  std::string xt, yt;
  for (size_t i = 0; i < rows.size(); ++i) {
    for (size_t k = 0; k < cols.size(); ++k) {
      std::snprintf(line, sizeof line, "%zu %zu %.4f %d\n", i, k, static_cast<double>(counts[i][k]) / per_row,
                    counts[i][k]);
      p.data += line;
    }
    p.data += "\n";
    yt += (i ? ", " : "") + ("'" + rows[i] + "' " + std::to_string(i));
  }
  for (size_t k = 0; k < cols.size(); ++k) xt += (k ? ", " : "") + ("'" + cols[k] + "' " + std::to_string(k));
  // noenhanced: effect names hold underscores, which gnuplot would otherwise draw as subscripts.
  p.script =
      "set terminal pngcairo noenhanced size 1000,800 font 'sans,10'\n"
      "set output 'confusion.png'\n"
      "set title '" + title + "'\n"
      "set xlabel '" + xlabel + "'\nset ylabel 'hidden'\n"
      "set xtics (" + xt + ") rotate by 45 right\nset ytics (" + yt + ")\n"
      "set yrange [" + std::to_string(rows.size()) + " - 0.5:-0.5]\nset xrange [-0.5:" +
      std::to_string(cols.size()) + " - 0.5]\n"
      "set cbrange [0:1]\nset palette defined (0 'white', 1 '#1f77b4')\nunset key\n"
      "plot 'confusion.dat' u 2:1:3 w image, '' u 2:1:($4 > 0 ? sprintf('%d', $4) : '') w labels font 'sans,8'\n";
  return p;
}

}  // namespace colosim
