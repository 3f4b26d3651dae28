#include "identify/tension/report.h"

#include <cmath>
#include <cstdio>

namespace colosim {

namespace {

nlohmann::json modelJson(const FittedModel& m) {
  nlohmann::json params = nlohmann::json::object();
  for (const ParamEstimate& p : m.params)
    params[p.name] = {{"value", p.value}, {"sd", std::isfinite(p.sd) ? nlohmann::json(p.sd) : nlohmann::json()},
                      {"unit", p.unit}};
  nlohmann::json j = scoreJson(m);
  j["law"] = m.lawName();
  j["params"] = params;
  return j;
}

// The residual diagnosis with the tension test's two measures of remaining structure.
void addStructure(const Diagnostics& d, nlohmann::json* j) {
  (*j)["lag1_autocorrelation"] = d.lag1_autocorrelation;
  (*j)["smooth_structure_N"] = d.smooth_structure_N;
}

}  // namespace

nlohmann::json holdDecayJson(const HoldDecay& h) {
  return {{"holds", h.holds}, {"decay_N", h.decay_N}, {"sd_N", h.sd_N}, {"relative", h.relative}};
}

nlohmann::json identifyJson(const TensionTest& t, const IdentifyResult& r) {
  const IdentifyOptions o;
  nlohmann::json j;
  j["file"] = t.file;
  j["rows"] = t.rows();
  j["sample_length_m"] = t.sample_length_m;
  j["cycles"] = r.cycles;
  j["hold_decay"] = holdDecayJson(r.hold_decay);
  j["reload_slope_ratio"] = r.reload_slope_ratio;
  j["baseline"] = modelJson(r.baseline);
  j["extended"] = modelJson(r.extended);
  addSelectionJson(selectionSummary(r),
                   "blocked cross-validation over loading cycles (fold = cycle mod " + std::to_string(o.folds) +
                       "), BIC as second opinion, on a working set of " + std::to_string(r.working_rows) + " rows",
                   o, false, &j);
  j["evidence"]["rule"]["min_pair_heldout_rmse_ratio"] = o.min_pair_heldout_ratio;
  if (!r.refuted_effects.empty())
    j["refuted"] = {{"effects", r.refuted_effects}, {"heldout_rmse_ratio", r.refuted_heldout_rmse_ratio}};
  addStructure(r.baseline_diagnostics, &j["evidence"]["baseline_residuals"]);
  addStructure(r.extended_diagnostics, &j["evidence"]["extended_residuals"]);
  return j;
}

void writeIdentifyReport(const std::string& dir, const TensionTest& t, const IdentifyResult& r) {
  std::string dat =
      "# time_s elongation_m strain rate_per_s measured_N baseline_N extended_N res_baseline_N res_extended_N "
      "time_in_hold_s cycle\n";
  char line[400];
  for (size_t k = 0; k < t.rows(); ++k) {
    std::snprintf(line, sizeof line, "%.4f %.6f %.6f %.6g %.4f %.5f %.5f %.5f %.5f %.3f %d\n", t.time_s[k],
                  t.elongation_m[k], r.strain[k], r.strain_rate_per_s[k], t.force_N[k], r.baseline.prediction_N[k],
                  r.extended.prediction_N[k], t.force_N[k] - r.baseline.prediction_N[k],
                  t.force_N[k] - r.extended.prediction_N[k], r.time_in_hold_s[k], r.cycle[k]);
    dat += line;
  }
  const std::string ext = r.effects.empty() ? "extended (= baseline: no effect)" : "extended (" + [&] {
    std::string s;
    for (const std::string& e : r.effects) s += (s.empty() ? "" : " + ") + e;
    return s;
  }() + ")";
  std::string gp =
      "set terminal pngcairo size 1100,650 font 'sans,10'\n"
      "set datafile commentschars '#'\n"
      "set key top left\nset grid\n"
      "set output 'force_time.png'\n"
      "set title 'Tension test: measured force and the two models'\n"
      "set xlabel 'time [s]'\nset ylabel 'force [N]'\n"
      "plot 'identify.dat' u 1:5 w p pt 7 ps 0.3 lc rgb '#999999' t 'measured', "
      "'' u 1:6 w l lw 1.5 lc rgb '#d62728' t 'baseline (Voigt, eq. 6)', "
      "'' u 1:7 w l lw 1.5 lc rgb '#1f77b4' t '" + ext + "'\n"
      "set output 'force_elongation.png'\n"
      "set title 'Force against elongation'\n"
      "set xlabel 'elongation [m]'\nset ylabel 'force [N]'\n"
      "plot 'identify.dat' u 2:5 w p pt 7 ps 0.3 lc rgb '#999999' t 'measured', "
      "'' u 2:6 w l lw 1.2 lc rgb '#d62728' t 'baseline', '' u 2:7 w l lw 1.2 lc rgb '#1f77b4' t 'extended'\n"
      "set output 'residuals.png'\n"
      "set terminal pngcairo size 1100,800 font 'sans,10'\n"
      "set multiplot layout 2,2 title 'Residuals (measured - model): baseline red, extended blue'\n"
      "unset key\nset ylabel 'residual [N]'\n"
      "set title 'against strain'\nset xlabel 'strain [-]'\n"
      "plot 'identify.dat' u 3:8 w p pt 7 ps 0.25 lc rgb '#d62728', '' u 3:9 w p pt 7 ps 0.25 lc rgb '#1f77b4'\n"
      "set title 'against strain rate'\nset xlabel 'strain rate [1/s]'\n"
      "plot 'identify.dat' u 4:8 w p pt 7 ps 0.25 lc rgb '#d62728', '' u 4:9 w p pt 7 ps 0.25 lc rgb '#1f77b4'\n"
      "set title 'against time within holds'\nset xlabel 'time since the hold began [s]'\n"
      "plot 'identify.dat' u ($10 >= 0 ? $10 : 1/0):8 w p pt 7 ps 0.25 lc rgb '#d62728', "
      "'' u ($10 >= 0 ? $10 : 1/0):9 w p pt 7 ps 0.25 lc rgb '#1f77b4'\n"
      "set title 'against cycle number'\nset xlabel 'loading cycle'\n"
      "plot 'identify.dat' u ($11 + 0.8 * (rand(0) - 0.5)):8 w p pt 7 ps 0.25 lc rgb '#d62728', "
      "'' u ($11 + 0.8 * (rand(0) - 0.5)):9 w p pt 7 ps 0.25 lc rgb '#1f77b4'\n"
      "unset multiplot\n";
  writeGnuplotReport(dir, {{"identify.dat", dat}}, gp, r.diagnosis, identifyJson(t, r));
}

}  // namespace colosim
