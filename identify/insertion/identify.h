// Identification at the organ level (issue 7; docs/organ-identification.md): replay a
// recorded insertion with the paper's model, show where its handle force departs from the
// measurement, name the extension(s) that explain the rest by held-out error and BIC,
// measure the gain.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "identify/insertion/replay.h"
#include "identify/selection.h"

namespace colosim {

/// A model of the organ replayed on a recording: the effects it has (ModelScore::effects,
/// empty for the paper's model), their magnitudes and its errors.
struct InsertionFit : ModelScore {
  OrganParams params;
  double offset_N = 0, offset_Nm = 0;  ///< sensor offsets, force [N] and torque [N m]
  double rmse_Nm = 0;                  ///< torque error [N m]
  double tip_rmse_m = -1;              ///< when the recording has a tip (else -1) [m]
  Prediction prediction;
};

struct InsertionIdentifyOptions : IdentifyOptions {
  double search_spacing_m = 0.03;     ///< coarser model while searching [m] (0: the parameter file's)
  int threads = 2;                    ///< replays run at once
  /// Add the fine-versus-coarse mismatch to the search's replays (false: measure what the
  /// search does without it, tools/organ_trials --no-mismatch).
  bool mismatch_term = true;
  /// Effects searched again at the data's resolution: the search's first choice and the
  /// round-1 candidates with the largest held-out ratios, this many in all.
  int fine_candidates = 3;
  /// Judge whether round 2 is needed on round 1's leaders refined at the data's resolution
  /// as well as on the search's own residual (false: only the search's, tools/organ_trials
  /// --search-judges-rounds, to measure what the shortcut changes).
  bool judge_rounds_at_data_resolution = true;
  /// The search steps in time coarser by the factor its spacing is coarser than the data's
  /// (3 cm against 1.5 cm: 2 ms against 1 ms), so that a step moves the model as far in
  /// control-point spacings as the data's model does (false: the setup's step,
  /// tools/organ_trials --search-at-data-step).
  bool search_step_with_spacing = true;
  /// Refine the search's choice first, and the other leaders only when it leaves more than
  /// the noise (false: every leader in any case, tools/organ_trials --refine-every-leader).
  bool refine_choice_first = true;
  /// While a refinement stage waits for its last replays, a free thread runs the next
  /// stage's replays as they would be if those still running came out worse (ReplayPool);
  /// the answers are the same bits either way (false: tools/organ_trials --no-guessing).
  bool guess_next_replays = true;
};

struct InsertionIdentifyResult {
  InsertionFit baseline, extended;
  std::vector<std::string> effects;
  double heldout_rmse_ratio = 1;
  bool unexplained = false;
  std::vector<CandidateEvidence> evidence;
  Diagnostics baseline_diagnostics, extended_diagnostics;  ///< profiles: motion, loop, insertion_depth
  int simulations = 0;
  int skipped_round = 0;              ///< round not run because the model is explained to the noise (0: none)
  double skipped_noise_sd_N = 0;      ///< the white-noise level that decided it [N]
  /// The round was judged not needed on round 1's leaders refined at the data's resolution
  /// (the search's own residual was above the noise).
  bool skipped_at_data_resolution = false;
  double seconds = 0;                 ///< wall-clock time of the identification [s]
  double search_spacing_m = 0;
  /// The data's resolution: the parameter file's spacing, at which the search's choice is
  /// refined and every reported figure is computed when it differs from the search's [m].
  double data_spacing_m = 0;
  std::vector<std::string> search_effects;      ///< what the coarse search chose (before the refinement)
  std::vector<CandidateEvidence> fine_evidence; ///< the refinement's candidates at the data's resolution
  bool fine_all_candidates = false;             ///< the leaders left structure: every candidate refined
  /// The search's choice, refined first, explained the data to the noise (held-out RMSE
  /// within min_heldout_ratio of the white-noise level), so these other leaders were not
  /// refined: nothing is left that they could explain better. Empty otherwise.
  std::vector<std::string> leaders_not_refined;
  double search_dt_s = 0;             ///< the search's time step [s]
  int fine_simulations = 0;           ///< replays at the data's resolution (in `simulations`)
  double mismatch_rms_N = 0;          ///< RMS fine-minus-coarse force of the last round's start model [N]
  /// Refinement replays started on a guess, and how many of them a stage then asked for
  /// (these depend on thread timing; the answers do not).
  int guessed_replays = 0, guessed_replays_used = 0;
  /// Effects the selection chose whose reported held-out gain is not above 1
  /// (gainConfirmed): not named; the data are then unexplained. Empty otherwise.
  std::vector<std::string> refuted_effects;
  double refuted_heldout_rmse_ratio = 0;  ///< their held-out gain
  int threads = 1;                    ///< replays run at once
  std::string diagnosis;
};

/// One held-out measure (issue 17): when the reported held-out gain of the named effects is
/// at or below 1, they become refuted_effects, no effect is named, the extended model is the
/// baseline and the gain 1. The caller then reports the data unexplained.
void refuteUnconfirmedGain(InsertionIdentifyResult* r);

/// Motion at row k by the recorded insertion speed (central difference): 0 push (> +2 mm/s),
/// 1 hold, 2 pull (< -2 mm/s).
int insertionMotion(const InsertionRecording& rec, size_t k);

/// Identifies with `setup` (the data's resolution: the parameter file's spacing); the
/// search replays at options.search_spacing_m with the fine-versus-coarse mismatch added, and
/// the result is refined and reported at the data's resolution.
InsertionIdentifyResult identifyInsertion(const InsertionRecording& rec, const ReplaySetup& setup,
                                          const InsertionIdentifyOptions& options = {});

/// The JSON object of `colosim identify --json` for an insertion (the keys of the tension
/// identification: effects, baseline, extended, gain, unexplained, evidence, ...).
nlohmann::json organIdentifyJson(const InsertionRecording& rec, const InsertionIdentifyResult& r);

/// A parameter file (colosim-params): the scenario's parameter file `base_params_path` with
/// the identified extensions of `fit` - contact.friction_coefficient, colon.bending_rigidity,
/// colon.mesentery_stiffening, and the tension-law effects as colon.tension_law (removed when
/// the fit has none) - so that `colosim run SCENARIO --params FILE` simulates the fitted model.
void writeOrganParameters(const std::string& path, const std::string& base_params_path, const InsertionFit& fit,
                          const std::string& source);

}  // namespace colosim
