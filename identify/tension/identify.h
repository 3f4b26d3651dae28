// Identification of the colon's tension law from a measured tension test
// (docs/identification.md): fit the paper's Voigt law, show where it fails, name the
// effect(s) that explain the rest by held-out prediction error, measure the gain.
#pragma once

#include <string>
#include <vector>

#include "core/extended_tension_law.h"
#include "identify/selection.h"
#include "identify/tension/tension_test.h"

namespace colosim {

/// One fitted parameter with its standard deviation (from the Gauss-Newton covariance
/// s^2 (J^T J)^-1; with coloured noise this is optimistic).
struct ParamEstimate {
  std::string name;
  double value = 0;
  double sd = 0;
  std::string unit;
};

/// A law fitted to a test: the effects it has (ModelScore::effects, empty for the Voigt
/// law), its parameters and its errors.
struct FittedModel : ModelScore {
  ExtendedLawParams law;              ///< the fitted law
  double offset_N = 0;                ///< fitted sensor offset [N]
  std::vector<ParamEstimate> params;  ///< law parameters, then offset_N
  std::vector<double> prediction_N;   ///< bench force of the full fit, per row [N]
  std::string lawName() const { return effects.empty() ? "voigt" : "extended"; }
};

/// The signature of relaxation (issue 17): the force decays while the strain is held. Over
/// the holds at positive strain (after kHoldSettleS, so that the actuator has stopped),
/// the baseline's residual averaged over the first third of each hold minus its average
/// over the last third. Data whose holds show no decay are not explained by relaxation,
/// however well a relaxing law fits them elsewhere (through a slack bench, relaxation
/// mimics a permanent set).
struct HoldDecay {
  int holds = 0;         ///< holds measured
  double decay_N = 0;    ///< summed decay over the holds [N]
  double sd_N = 0;       ///< its standard deviation from the residual's noise [N]
  double relative = 0;   ///< summed decay over the summed force at the holds [-]
  double z() const { return sd_N > 0 ? decay_N / sd_N : 0.0; }
};

struct IdentifyResult {
  FittedModel baseline;                 ///< the Voigt law (eq. 6)
  FittedModel extended;                 ///< with the chosen effects (= baseline if none)
  std::vector<std::string> effects;     ///< chosen effects, most important first
  double heldout_rmse_ratio = 1;        ///< baseline / extended held-out error
  /// Effects the selection chose but whose held-out gain, refitted on every row, was not
  /// above 1 (gainConfirmed): not named, and the data are unexplained. Empty otherwise.
  std::vector<std::string> refuted_effects;
  double refuted_heldout_rmse_ratio = 0;  ///< that gain
  bool unexplained = false;
  std::vector<CandidateEvidence> evidence;
  Diagnostics baseline_diagnostics, extended_diagnostics;
  std::vector<double> strain, strain_rate_per_s;  ///< per row
  std::vector<int> cycle;               ///< loading cycle of each row (0-based)
  std::vector<int> fold;                ///< cross-validation fold of each row
  std::vector<double> time_in_hold_s;   ///< time since the hold began, -1 outside holds
  int cycles = 0;
  HoldDecay hold_decay;                 ///< the force's decay at held strain
  /// Softening's signature: the median slope dF/de of the reloadings (loading below a strain
  /// reached before) over that of the virgin loadings (loading at the largest strain so far),
  /// both fitted per loading run in the force window 0.15-0.4 x the largest reloading force.
  /// Softening lowers the slope at a given force on reloading; a set shifts the curve along
  /// the strain and leaves it. -1 when either kind of loading has no run in the window.
  double reload_slope_ratio = -1;
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
