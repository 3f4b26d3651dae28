// What `colosim identify` writes, for both data sources: the JSON pieces of the selection
// (scores, evidence, rule, residual diagnosis, gain) and a report folder with PNG plots made
// by gnuplot (Debian's gnuplot-nox, pngcairo terminal). Each source adds its own keys and
// plots (identify/tension/report.h, identify/insertion/report.h).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "identify/selection.h"

namespace colosim {

/// effects, rmse_N, heldout_rmse_N, aic, bic, n_params of a model (the source adds law and params).
nlohmann::json scoreJson(const ModelScore& m);

/// The keys of `colosim identify --json` common to both sources: effects, gain (held-out and
/// full-fit RMSE ratios, both held-out errors), unexplained, diagnosis, and evidence (method,
/// rule, candidates, baseline_residuals, extended_residuals). `with_magnitudes` adds each
/// candidate's value and simulations (insertion). docs/identification.md lists every key.
struct SelectionSummary {
  const ModelScore* baseline = nullptr;
  const ModelScore* extended = nullptr;
  std::vector<std::string> effects;
  double heldout_rmse_ratio = 1;
  bool unexplained = false;
  const std::vector<CandidateEvidence>* evidence = nullptr;
  const Diagnostics* baseline_diagnostics = nullptr;
  const Diagnostics* extended_diagnostics = nullptr;
  std::string diagnosis;
};
/// One candidate's evidence (round, effect, model, errors, ratio, dAIC, dBIC, pays, chosen;
/// with_magnitude: value and simulations).
nlohmann::json candidateJson(const CandidateEvidence& e, bool with_magnitude);

/// The summary of a result of either source (IdentifyResult, InsertionIdentifyResult).
template <class Result>
SelectionSummary selectionSummary(const Result& r) {
  return {&r.baseline, &r.extended, r.effects, r.heldout_rmse_ratio, r.unexplained, &r.evidence,
          &r.baseline_diagnostics, &r.extended_diagnostics, r.diagnosis};
}
void addSelectionJson(const SelectionSummary& s, const std::string& method, const IdentifyOptions& o,
                      bool with_magnitudes, nlohmann::json* j);

/// The residual diagnosis: rmse_N, noise_sd_N, rmse_over_noise and residual_profiles (per
/// variable: bins or bin_centre, mean_residual_N, count, structure_N).
nlohmann::json diagnosticsJson(const Diagnostics& d);

/// A data file of a report folder: its name in the folder and its bytes.
struct ReportFile {
  std::string name;
  std::string text;
};

/// Writes a gnuplot report folder and runs it: creates dir/ if missing, writes the data
/// files, the script as report.gp, diagnosis.txt and result as identify.json, then runs
/// `gnuplot report.gp` in dir/ (its output in gnuplot.log). Throws std::runtime_error when
/// the folder or a file cannot be written or gnuplot fails.
void writeGnuplotReport(const std::string& dir, const std::vector<ReportFile>& data, const std::string& script,
                        const std::string& diagnosis, const nlohmann::json& result);

}  // namespace colosim
