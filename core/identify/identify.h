// Identification of the colon's tension law from a measured tension test
// (docs/identification.md): fit the paper's Voigt law, show where it fails, name the
// effect(s) that explain the rest by held-out prediction error, measure the gain.
#pragma once

#include <string>
#include <vector>

#include "core/extended_tension_law.h"
#include "core/identify/measurement.h"

namespace colosim {

/// One fitted parameter with its standard deviation (from the Gauss-Newton covariance
/// s^2 (J^T J)^-1; with coloured noise this is optimistic).
struct ParamEstimate {
  std::string name;
  double value = 0;
  double sd = 0;
  std::string unit;
};

/// A law fitted to a test: the effects it has, its parameters and its errors.
struct FittedModel {
  std::vector<std::string> effects;   ///< empty for the Voigt law
  ExtendedLawParams law;              ///< the fitted law
  double offset_N = 0;                ///< fitted sensor offset [N]
  std::vector<ParamEstimate> params;  ///< law parameters, then offset_N
  double rmse_N = 0;                  ///< fit on all rows [N]
  double heldout_rmse_N = 0;          ///< pooled error on the held-out folds [N]
  double aic = 0, bic = 0;            ///< Gaussian information criteria of the full fit
  int n_params = 0;
  std::vector<double> prediction_N;   ///< bench force of the full fit, per row [N]
  std::string lawName() const { return effects.empty() ? "voigt" : "extended"; }
};

/// What one test of one candidate measured.
struct CandidateEvidence {
  int round = 0;                       ///< 1: first effect, 2: second, 3: exchange of the first
  std::string effect;                  ///< the candidate added
  std::vector<std::string> model;      ///< the effects of the model tested
  double rmse_N = 0, heldout_rmse_N = 0;
  double heldout_ratio = 0;            ///< held-out error before / with the candidate
  double delta_aic = 0, delta_bic = 0; ///< with the candidate minus before
  bool pays = false;                   ///< passes both the held-out and the BIC test
  bool chosen = false;                 ///< the best of its round and added
};

/// Residual structure in bins of one variable: mean residual and count per bin.
struct ResidualProfile {
  std::string variable;              ///< strain, strain_rate_per_s, time_in_hold_s, cycle
  std::vector<double> bin_centre;
  std::vector<double> mean_residual_N;
  std::vector<int> count;
  double structure_N = 0;            ///< count-weighted RMS of the bin means [N]
};

struct Diagnostics {
  double rmse_N = 0;
  double noise_sd_N = 0;          ///< white-noise level from differenced residuals [N]
  double lag1_autocorrelation = 0;
  double smooth_structure_N = 0;  ///< RMS of the residual smoothed over ~2 s [N]
  std::vector<ResidualProfile> profiles;
};

struct IdentifyOptions {
  int folds = 3;                     ///< blocked cross-validation folds
  double min_heldout_ratio = 1.05;   ///< an effect must cut the held-out error by 5 %...
  double max_delta_bic = -10.0;      ///< ...and lower the BIC by at least 10
  int max_effects = 2;
  /// Structure is "unexplained" when the best model's RMSE exceeds this multiple of the
  /// white-noise level.
  double unexplained_rmse_over_noise = 1.6;
};

struct IdentifyResult {
  FittedModel baseline;                 ///< the Voigt law (eq. 6)
  FittedModel extended;                 ///< with the chosen effects (= baseline if none)
  std::vector<std::string> effects;     ///< chosen effects, most important first
  double heldout_rmse_ratio = 1;        ///< baseline / extended held-out error
  bool unexplained = false;
  std::vector<CandidateEvidence> evidence;
  Diagnostics baseline_diagnostics, extended_diagnostics;
  std::vector<double> strain, strain_rate_per_s;  ///< per row
  std::vector<int> cycle;               ///< loading cycle of each row (0-based)
  std::vector<int> fold;                ///< cross-validation fold of each row
  std::vector<double> time_in_hold_s;   ///< time since the hold began, -1 outside holds
  int cycles = 0;
  int working_rows = 0;                 ///< rows of the (block-averaged) selection set
  std::string diagnosis;                ///< the text of the diagnosis, for people
};

/// Runs the whole identification. Deterministic.
IdentifyResult identifyTension(const TensionTest& test, const IdentifyOptions& options = {});

/// Fits a law with the given effects (plus a sensor offset) to every row of a test,
/// starting from the parameters of `start` when given. No cross-validation (its
/// heldout_rmse_N is not meaningful). For tools and tests.
FittedModel fitTensionLaw(const TensionTest& test, const std::vector<std::string>& effects,
                          const FittedModel* start = nullptr);

}  // namespace colosim
