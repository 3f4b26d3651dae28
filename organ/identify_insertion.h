// Identification at the organ level (issue 7; docs/organ-identification.md): replay a
// recorded insertion with the paper's model, show where its handle force departs from the
// measurement, name the extension(s) that explain the rest by held-out error and BIC,
// measure the gain.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "organ/replay.h"

namespace colosim {

struct OrganFit {
  std::vector<std::string> effects;  ///< empty for the paper's model
  OrganParams params;
  double offset_N = 0, offset_Nm = 0;  ///< sensor offsets, force and torque
  double rmse_N = 0, heldout_rmse_N = 0, rmse_Nm = 0;
  double tip_rmse_m = -1;              ///< when the recording has a tip (else -1)
  double aic = 0, bic = 0;
  int n_params = 0;
  Prediction prediction;
};

struct OrganEvidence {
  int round = 0;
  std::string effect;
  std::vector<std::string> model;
  double value = 0;                    ///< fitted magnitude of the candidate
  double rmse_N = 0, heldout_rmse_N = 0, heldout_ratio = 0, delta_aic = 0, delta_bic = 0;
  bool pays = false, chosen = false;
  int simulations = 0;
};

/// Mean force residual in bins of one variable (push / hold / pull, in a loop or not, depth).
struct OrganProfile {
  std::string variable;
  std::vector<std::string> bin;
  std::vector<double> mean_residual_N;
  std::vector<int> count;
  double structure_N = 0;  ///< count-weighted RMS of the bin means [N]
};

struct OrganDiagnostics {
  double rmse_N = 0, noise_sd_N = 0, rmse_over_noise = 0;
  std::vector<OrganProfile> profiles;
};

struct OrganIdentifyOptions {
  double search_spacing_m = 0.03;     ///< coarser model while searching [m] (0: the parameter file's)
  int folds = 3;                      ///< contiguous time blocks
  double min_heldout_ratio = 1.05;    ///< as the tension identification
  double max_delta_bic = -10.0;
  int max_effects = 2;
  double unexplained_rmse_over_noise = 1.6;
  int threads = 2;
};

struct OrganIdentifyResult {
  OrganFit baseline, extended;
  std::vector<std::string> effects;
  double heldout_rmse_ratio = 1;
  bool unexplained = false;
  std::vector<OrganEvidence> evidence;
  OrganDiagnostics baseline_diagnostics, extended_diagnostics;
  int simulations = 0;
  int skipped_round = 0;              ///< round not run because the model is explained to the noise (0: none)
  double skipped_noise_sd_N = 0;      ///< the white-noise level that decided it [N]
  double seconds = 0;                 ///< wall-clock time of the identification [s]
  double search_spacing_m = 0;
  int threads = 1;                    ///< replays run at once
  std::string diagnosis;
};

/// Motion at row k by the recorded insertion speed (central difference): 0 push (> +2 mm/s),
/// 1 hold, 2 pull (< -2 mm/s).
int insertionMotion(const InsertionRecording& rec, size_t k);

OrganIdentifyResult identifyInsertion(const InsertionRecording& rec, const ReplaySetup& setup,
                                      const OrganIdentifyOptions& options = {});

/// The JSON object of `colosim identify --json` for an insertion (the keys of the tension
/// identification: effects, baseline, extended, gain, unexplained, evidence, ...).
nlohmann::json organIdentifyJson(const InsertionRecording& rec, const OrganIdentifyResult& r);

/// A parameter file (colosim-params): the scenario's parameter file `base_params_path` with
/// the identified extensions of `fit` - contact.friction_coefficient, colon.bending_rigidity,
/// colon.mesentery_stiffening, and the tension-law effects as colon.tension_law (removed when
/// the fit has none) - so that `colosim run SCENARIO --params FILE` simulates the fitted model.
void writeOrganParameters(const std::string& path, const std::string& base_params_path, const OrganFit& fit,
                          const std::string& source);

}  // namespace colosim
