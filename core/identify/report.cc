#include "core/identify/report.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace colosim {

namespace {

nlohmann::json modelJson(const FittedModel& m) {
  nlohmann::json params = nlohmann::json::object();
  for (const ParamEstimate& p : m.params)
    params[p.name] = {{"value", p.value}, {"sd", std::isfinite(p.sd) ? nlohmann::json(p.sd) : nlohmann::json()},
                      {"unit", p.unit}};
  return {{"law", m.lawName()}, {"effects", m.effects}, {"params", params}, {"rmse_N", m.rmse_N},
          {"heldout_rmse_N", m.heldout_rmse_N}, {"aic", m.aic}, {"bic", m.bic}, {"n_params", m.n_params}};
}

nlohmann::json diagnosticsJson(const Diagnostics& d) {
  nlohmann::json profiles = nlohmann::json::object();
  for (const ResidualProfile& p : d.profiles)
    profiles[p.variable] = {{"bin_centre", p.bin_centre}, {"mean_residual_N", p.mean_residual_N},
                            {"count", p.count}, {"structure_N", p.structure_N}};
  return {{"rmse_N", d.rmse_N}, {"noise_sd_N", d.noise_sd_N}, {"rmse_over_noise", d.rmse_N / std::max(1e-300, d.noise_sd_N)},
          {"lag1_autocorrelation", d.lag1_autocorrelation}, {"smooth_structure_N", d.smooth_structure_N},
          {"residual_profiles", profiles}};
}

void writeText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error(p.string() + ": cannot write the file");
}

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

nlohmann::json identifyJson(const TensionTest& t, const IdentifyResult& r) {
  nlohmann::json candidates = nlohmann::json::array();
  for (const CandidateEvidence& e : r.evidence)
    candidates.push_back({{"round", e.round}, {"effect", e.effect}, {"model", e.model}, {"rmse_N", e.rmse_N},
                          {"heldout_rmse_N", e.heldout_rmse_N}, {"heldout_rmse_ratio", e.heldout_ratio},
                          {"delta_aic", e.delta_aic}, {"delta_bic", e.delta_bic}, {"pays", e.pays},
                          {"chosen", e.chosen}});
  const IdentifyOptions o;
  nlohmann::json j;
  j["file"] = t.file;
  j["rows"] = t.rows();
  j["sample_length_m"] = t.sample_length_m;
  j["cycles"] = r.cycles;
  j["effects"] = r.effects;
  j["baseline"] = modelJson(r.baseline);
  j["extended"] = modelJson(r.extended);
  j["gain"] = {{"heldout_rmse_ratio", r.heldout_rmse_ratio},
               {"rmse_ratio", r.baseline.rmse_N / r.extended.rmse_N},
               {"baseline_heldout_rmse_N", r.baseline.heldout_rmse_N},
               {"extended_heldout_rmse_N", r.extended.heldout_rmse_N}};
  j["unexplained"] = r.unexplained;
  j["evidence"] = {
      {"method", "blocked cross-validation over loading cycles (fold = cycle mod " + std::to_string(o.folds) +
                     "), BIC as second opinion, on a working set of " + std::to_string(r.working_rows) + " rows"},
      {"rule", {{"min_heldout_rmse_ratio", o.min_heldout_ratio}, {"max_delta_bic", o.max_delta_bic},
                {"max_effects", o.max_effects}, {"unexplained_rmse_over_noise", o.unexplained_rmse_over_noise}}},
      {"candidates", candidates},
      {"baseline_residuals", diagnosticsJson(r.baseline_diagnostics)},
      {"extended_residuals", diagnosticsJson(r.extended_diagnostics)}};
  j["diagnosis"] = r.diagnosis;
  return j;
}

void writeGnuplotReport(const std::string& dir, const std::vector<ReportFile>& data, const std::string& script,
                        const std::string& diagnosis, const nlohmann::json& result) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw std::runtime_error(dir + ": cannot create the report folder");
  const fs::path d(dir);
  for (const ReportFile& f : data) writeText(d / f.name, f.text);
  writeText(d / "report.gp", script);
  writeText(d / "diagnosis.txt", diagnosis);
  writeText(d / "identify.json", result.dump(2) + "\n");
  const std::string cmd = "cd " + shellQuote(d.string()) + " && gnuplot report.gp > gnuplot.log 2>&1";
  if (std::system(cmd.c_str()) != 0)
    throw std::runtime_error("gnuplot failed (see " + (d / "gnuplot.log").string() + ")");
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
