#include "identify/report.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "trainer/report_files.h"

namespace colosim {

nlohmann::json candidateJson(const CandidateEvidence& e, bool with_magnitude) {
  nlohmann::json c = {{"round", e.round}, {"effect", e.effect}, {"model", e.model}, {"rmse_N", e.rmse_N},
                      {"heldout_rmse_N", e.heldout_rmse_N}, {"heldout_rmse_ratio", e.heldout_ratio},
                      {"delta_aic", e.delta_aic}, {"delta_bic", e.delta_bic}, {"pays", e.pays},
                      {"chosen", e.chosen}};
  if (e.signature_rmse_N >= 0) c["signature_rmse_N"] = e.signature_rmse_N;
  if (e.without_signature) c["without_signature"] = true;
  if (with_magnitude) {
    c["value"] = e.value;
    c["simulations"] = e.simulations;
  }
  return c;
}

nlohmann::json scoreJson(const ModelScore& m) {
  return {{"effects", m.effects}, {"rmse_N", m.rmse_N}, {"heldout_rmse_N", m.heldout_rmse_N},
          {"aic", m.aic},         {"bic", m.bic},       {"n_params", m.n_params}};
}

nlohmann::json diagnosticsJson(const Diagnostics& d) {
  nlohmann::json profiles = nlohmann::json::object();
  for (const ResidualProfile& p : d.profiles) {
    nlohmann::json& q = profiles[p.variable];
    if (p.bin.empty()) q["bin_centre"] = p.bin_centre;
    else q["bins"] = p.bin;
    q["mean_residual_N"] = p.mean_residual_N;
    q["count"] = p.count;
    q["structure_N"] = p.structure_N;
  }
  return {{"rmse_N", d.rmse_N}, {"noise_sd_N", d.noise_sd_N}, {"rmse_over_noise", d.rmse_over_noise},
          {"residual_profiles", profiles}};
}

void addSelectionJson(const SelectionSummary& s, const std::string& method, const IdentifyOptions& o,
                      bool with_magnitudes, nlohmann::json* j) {
  (*j)["effects"] = s.effects;
  (*j)["gain"] = {{"heldout_rmse_ratio", s.heldout_rmse_ratio},
                  {"rmse_ratio", s.baseline->rmse_N / std::max(s.extended->rmse_N, 1e-300)},
                  {"baseline_heldout_rmse_N", s.baseline->heldout_rmse_N},
                  {"extended_heldout_rmse_N", s.extended->heldout_rmse_N}};
  (*j)["unexplained"] = s.unexplained;
  nlohmann::json candidates = nlohmann::json::array();
  for (const CandidateEvidence& e : *s.evidence) candidates.push_back(candidateJson(e, with_magnitudes));
  (*j)["evidence"] = {
      {"method", method},
      {"rule", {{"min_heldout_rmse_ratio", o.min_heldout_ratio}, {"max_delta_bic", o.max_delta_bic},
                {"max_effects", o.max_effects}, {"unexplained_rmse_over_noise", o.unexplained_rmse_over_noise}}},
      {"candidates", candidates},
      {"baseline_residuals", diagnosticsJson(*s.baseline_diagnostics)},
      {"extended_residuals", diagnosticsJson(*s.extended_diagnostics)}};
  (*j)["diagnosis"] = s.diagnosis;
}

void writeGnuplotReport(const std::string& dir, const std::vector<ReportFile>& data, const std::string& script,
                        const std::string& diagnosis, const nlohmann::json& result) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw std::runtime_error(dir + ": cannot create the report folder");
  const fs::path d(dir);
  for (const ReportFile& f : data) writeReportText(d / f.name, f.text);
  writeReportText(d / "report.gp", script);
  writeReportText(d / "diagnosis.txt", diagnosis);
  writeReportText(d / "identify.json", result.dump(2) + "\n");
  runReportGnuplot(d);
}

}  // namespace colosim
