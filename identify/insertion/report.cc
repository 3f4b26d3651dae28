#include "identify/insertion/report.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "identify/report.h"

namespace colosim {

namespace {

// The extended model's label, e.g. "extended (colon_bending 0.0228 N m^2)".
std::string extendedLabel(const InsertionIdentifyResult& r) {
  if (r.effects.empty()) return "extended (= paper: no effect named)";
  std::string s;
  char buf[128];
  for (const std::string& e : r.effects) {
    const auto pu = organEffectParameter(e);
    std::snprintf(buf, sizeof buf, "%s%s %.3g %s", s.empty() ? "" : " + ", e.c_str(),
                  organEffectValue(r.extended.params, e), pu.second.c_str());
    s += buf;
  }
  return "extended (" + s + ")";
}

}  // namespace

void writeOrganReport(const std::string& dir, const InsertionRecording& rec, const InsertionIdentifyResult& r) {
  const InsertionFit& b = r.baseline;
  const InsertionFit& x = r.extended;
  std::string dat =
      "# predictions include each model's fitted sensor offsets; motion 0 push, 1 hold, 2 pull\n"
      "# 1 time_s  2 insertion_m  3 motion  4 measured_N  5 paper_N  6 extended_N  7 measured_Nm  8 paper_Nm  "
      "9 extended_Nm  10 res_paper_N  11 res_extended_N\n";
  char line[400];
  for (size_t k = 0; k < rec.rows(); ++k) {
    const double fb = b.prediction.force_N[k] + b.offset_N, fx = x.prediction.force_N[k] + x.offset_N;
    const double tb = b.prediction.torque_Nm[k] + b.offset_Nm, tx = x.prediction.torque_Nm[k] + x.offset_Nm;
    std::snprintf(line, sizeof line, "%.4f %.6f %d %.5f %.5f %.5f %.6f %.6f %.6f %.5f %.5f\n", rec.time_s[k],
                  rec.input[k].insertion_m, insertionMotion(rec, k), rec.force_N[k], fb, fx, rec.torque_Nm[k], tb, tx,
                  rec.force_N[k] - fb, rec.force_N[k] - fx);
    dat += line;
  }
  const std::string ext = extendedLabel(r);
  // Force axes span the 0.5-99.5 % quantiles of the measured force (with a margin): the
  // replays have brief spikes (contacts made in one step) that would flatten the rest.
  std::vector<double> sorted = rec.force_N;
  std::sort(sorted.begin(), sorted.end());
  const double lo = sorted[static_cast<size_t>(0.005 * (sorted.size() - 1))];
  const double hi = sorted[static_cast<size_t>(0.995 * (sorted.size() - 1))];
  const double margin = 0.15 * (hi - lo) + 0.1;
  int outside = 0;
  for (double f : rec.force_N) outside += f < lo - margin || f > hi + margin;
  char yr[160];
  std::snprintf(yr, sizeof yr, "force_lo = %.4f\nforce_hi = %.4f\n", lo - margin, hi + margin);
  const std::string yrange_note_cmd = yr;
  const std::string clipped = outside ? " (" + std::to_string(outside) + " measured spikes beyond the axis)" : "";
  // Colours: measured grey, paper red, extended blue; push / pull as filled / open markers.
  const std::string push = "($3 == 0 ? $2 : 1/0)", pull = "($3 == 2 ? $2 : 1/0)";
  auto depthPanel = [&](const std::string& title, int meas, int model, const std::string& colour) {
    const std::string m = std::to_string(meas), p = std::to_string(model);
    return "set title '" + title + "'\n"
           "plot 'insertion.dat' u " + push + ":" + m + " w p pt 7 ps 0.35 lc rgb '#9ecae1' t 'measured, push', "
           "'' u " + pull + ":" + m + " w p pt 7 ps 0.35 lc rgb '#fdae6b' t 'measured, pull', "
           "'' u " + push + ":" + p + " w p pt 7 ps 0.15 lc rgb '" + colour + "' t 'model, push', "
           "'' u " + pull + ":" + p + " w p pt 6 ps 0.3 lc rgb '" + colour + "' t 'model, pull'\n";
  };
  std::string gp =
      "set terminal pngcairo noenhanced size 1100,800 font 'sans,10'\n"
      "set datafile commentschars '#'\n"
      "set key below horizontal\nset grid\n" + yrange_note_cmd +
      // Over time.
      "set output 'force_time.png'\n"
      "set multiplot layout 2,1 title 'Recorded insertion: measured handle force and torque, the paper''s model "
      "and the extended model'\n"
      "set xlabel 'time [s]'\nset ylabel 'handle force [N]'\nset title 'force" + clipped + "'\n"
      "set yrange [force_lo:force_hi]\n"
      "plot 'insertion.dat' u 1:4 w p pt 7 ps 0.3 lc rgb '#999999' t 'measured', "
      "'' u 1:5 w l lw 1.3 lc rgb '#d62728' t 'paper''s model', "
      "'' u 1:6 w l lw 1.3 lc rgb '#1f77b4' t '" + ext + "'\n"
      "set autoscale y\nset ylabel 'handle torque [N m]'\nset title 'torque'\n"
      "plot 'insertion.dat' u 1:7 w p pt 7 ps 0.3 lc rgb '#999999' t 'measured', "
      "'' u 1:8 w l lw 1.3 lc rgb '#d62728' t 'paper''s model', "
      "'' u 1:9 w l lw 1.3 lc rgb '#1f77b4' t 'extended'\n"
      "unset multiplot\n"
      // Against depth, push and pull apart.
      "set output 'force_depth.png'\n"
      "set terminal pngcairo noenhanced size 1200,900 font 'sans,10'\n"
      "set multiplot layout 2,2 title 'Against insertion depth, push and pull apart (hold rows left out)'\n"
      "set xlabel 'insertion depth [m]'\nset ylabel 'handle force [N]'\nset yrange [force_lo:force_hi]\n" +
      depthPanel("force: paper''s model", 4, 5, "#d62728") + depthPanel("force: " + ext, 4, 6, "#1f77b4") +
      "set autoscale y\nset ylabel 'handle torque [N m]'\n" + depthPanel("torque: paper''s model", 7, 8, "#d62728") +
      depthPanel("torque: extended", 7, 9, "#1f77b4") +
      "unset multiplot\n"
      // Residuals.
      "set output 'residuals.png'\n"
      "set terminal pngcairo noenhanced size 1100,800 font 'sans,10'\n"
      "set multiplot layout 2,1 title 'Force residual (measured - model): paper red, extended blue'\n"
      "set ylabel 'residual [N]'\nset yrange [-(force_hi - force_lo) / 2:(force_hi - force_lo) / 2]\n"
      "set title 'against insertion depth (filled: push, open: pull)'\nset xlabel 'insertion depth [m]'\n"
      "plot 'insertion.dat' u " + push + ":10 w p pt 7 ps 0.3 lc rgb '#d62728' t 'paper, push', "
      "'' u " + pull + ":10 w p pt 6 ps 0.4 lc rgb '#d62728' t 'paper, pull', "
      "'' u " + push + ":11 w p pt 7 ps 0.3 lc rgb '#1f77b4' t 'extended, push', "
      "'' u " + pull + ":11 w p pt 6 ps 0.4 lc rgb '#1f77b4' t 'extended, pull'\n"
      "set title 'over time'\nset xlabel 'time [s]'\n"
      "plot 'insertion.dat' u 1:10 w p pt 7 ps 0.3 lc rgb '#d62728' t 'paper', "
      "'' u 1:11 w p pt 7 ps 0.3 lc rgb '#1f77b4' t 'extended'\n"
      "unset multiplot\n";
  writeGnuplotReport(dir, {{"insertion.dat", dat}}, gp, r.diagnosis, organIdentifyJson(rec, r));
}

}  // namespace colosim
