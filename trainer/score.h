// Scoring a session from its per-step telemetry: the measures that separated experts
// from novices in published simulator validity studies (../shared/reference/parameters.md).
// Definitions, units and thresholds: docs/file-formats.md ("Scores").
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainer/telemetry.h"

namespace colosim {

/// Thresholds of the scores, with units. Defaults are the named constants below; a
/// scenario may override them (its "scoring" object).
struct ScoreOptions {
  /// Caecum reached when the tip is within this distance of the caecal pole [m].
  double caecum_reach_m = 0.03;
  /// Wall force above which pressure is excessive [N] (tuning: a few N on a 1 cm^2 tip
  /// area is ~50 kPa, well above the ~10 kPa that blanches mucosa).
  double excessive_wall_force_N = 5.0;
  /// Excessive pressure counts as an episode when it lasts longer than this [s].
  double episode_min_s = 0.5;
  /// Discomfort when the colon is stretched (Telemetry::colon_stretch) beyond this [-]
  /// (tuning: 3 % longer than at rest; the adult colon hanging at rest reaches 0.7 %, at
  /// the hepatic flexure, so rest and sag are never discomfort).
  double discomfort_strain = 0.03;
  /// The mesentery overloaded when its stretch (Telemetry::mesentery_stretch) exceeds this
  /// [-] (mesentery_stretch_time_pct; tuning: the adult colon hanging at rest reaches 3.2
  /// at the hepatic flexure, whose attachments carry the transverse colon; 5 keeps rest
  /// out). Until session 21 this was the discomfort threshold.
  double discomfort_stretch = 5.0;
  /// A loop is present when |loop_turns| is at least this [turns].
  double loop_turns = 0.5;
  /// A wall patch counts as visualised once seen for this long in total [s].
  double patch_seen_min_s = 0.5;
  /// Handle force above which time is counted as high force [N] (Appleyard et al. 2000:
  /// above 10 N only ~5 % of the time).
  double high_handle_force_N = 10.0;
  /// Telemetry with time_s <= this is not scored (a scripted start such as forming
  /// the loop is set-up, not performance) [s]. Times in the scores count from here.
  double start_s = 0.0;
};

/// Accumulates the scores of one phase (the whole session, insertion or withdrawal).
class PhaseScore {
 public:
  explicit PhaseScore(const ScoreOptions& options) : o_(options) {}
  /// One record; dt_s is the time it covers [s]; `prev` the record before it (any
  /// phase), nullptr for the first, for path lengths.
  void add(const Telemetry& t, double dt_s, const Telemetry* prev);
  /// The scores of this phase as a JSON object (keys carry their units).
  nlohmann::json json() const;

  double duration_s = 0;
  double peak_handle_force_N = 0;     ///< largest |axial handle force| [N]
  double peak_push_N = 0;             ///< largest push [N]
  double peak_pull_N = 0;             ///< largest pull (reported positive) [N]
  double peak_handle_torque_Nm = 0;   ///< largest |handle torque| [N m]
  double handle_force_integral_Ns = 0;  ///< integral of |handle force| dt [N s]
  double handle_torque_integral_Nms = 0;///< integral of |handle torque| dt [N m s]
  double high_force_time_s = 0;       ///< time with |handle force| > high_handle_force_N [s]
  double peak_wall_force_N = 0;       ///< largest wall contact force of one scope segment [N]
  double peak_wall_force_total_N = 0; ///< largest total wall contact force of the whole scope [N]
  double wall_force_integral_Ns = 0;  ///< integral of the total wall contact force dt [N s]
  /// Shaft pushed in that the tip did not follow [m]: the sum over steps of
  /// max(0, d inserted - max(0, d tip arclength)) over the steps that push in
  /// (Telemetry::inserted_m, tip_arclength_m; docs/design-studies.md).
  double shaft_movement_without_tip_progress_m = 0;
  int excessive_pressure_episodes = 0;
  double excessive_pressure_time_s = 0;  ///< time above the wall force threshold [s]
  double discomfort_index_s = 0;      ///< integral of max(0, colon stretch - threshold) dt [s]
  double discomfort_time_s = 0;       ///< time with the colon stretched beyond the threshold [s]
  double peak_colon_stretch = 0;      ///< [-]
  double peak_mesentery_stretch = 0;  ///< [-]
  double mesentery_stretch_time_s = 0;  ///< time with the mesentery stretch above discomfort_stretch [s]
  double loop_time_s = 0;             ///< time with a loop [s]
  double max_loop_turns = 0;          ///< largest |loop_turns| [turns]
  double loop_writhe_max = 0;         ///< largest |loop_writhe| [turns]
  /// Smallest present/rest length ratio reached by each anatomy region [-], by name.
  std::map<std::string, double> region_length_ratio_min;
  double redout_time_s = 0;           ///< time with the tip against the wall [s]
  double lumen_visible_time_s = 0;    ///< time with the lumen in view [s]
  int lumen_lost_count = 0;           ///< lumen visible -> not visible transitions
  double tip_path_m = 0;              ///< path length of the tip [m]
  double insertion_path_m = 0;        ///< sum of |d insertion| at the handle [m]
  double rotation_path_rad = 0;       ///< sum of |d rotation| at the handle [rad]
  double knob_path_rad = 0;           ///< sum of |d knob| over both knobs [rad]
  int patch_count = 0;
  std::map<int, double> patch_seen_s; ///< cumulative time each patch was seen [s]

 private:
  ScoreOptions o_;
  double episode_s_ = 0;          ///< length of the current above-threshold run [s]
  bool episode_counted_ = false;
  bool lumen_was_visible_ = true; ///< the lumen is taken as visible before the first record
};

/// Consumes one Telemetry record per step and produces the session's scores: the whole
/// session, insertion (until the caecum is reached, or the whole session when it never
/// is) and withdrawal (after it) scored separately.
class Scorer {
 public:
  explicit Scorer(const ScoreOptions& options = {});
  void add(const Telemetry& t);
  /// The scores as a JSON object: the keys of PhaseScore::json for the whole session,
  /// plus time_to_caecum_s and insertion_at_caecum_m (null when not reached), "insertion", "withdrawal" (null when
  /// the caecum was not reached) and "units" (the unit of every key).
  nlohmann::json json() const;
  /// The unit of every key of json() ("1" for counts, "-" for ratios).
  static const std::map<std::string, std::string>& units();

  std::optional<double> time_to_caecum_s() const { return time_to_caecum_s_; }
  /// Scope length past the anus when the caecum was first reached [m] (Telemetry::inserted_m).
  std::optional<double> insertion_at_caecum_m() const { return insertion_at_caecum_m_; }
  /// Steps in which a solver limit engaged (Telemetry::solver_limited > 0), and runs of
  /// such steps (episodes), over the whole session including a scripted set-up: what the
  /// session's solver_limited events report (docs/hardening.md).
  long solverLimitedSteps() const { return limited_steps_; }
  long solverLimitedEpisodes() const { return limited_episodes_; }
  /// The contact topology over the whole session, every step including a set-up
  /// (Telemetry::track_jump_m, wall_penetration_m, lumen_exit): the largest track jump [m],
  /// the deepest penetration [m], the steps with a slice centre out of its lumen.
  double maxTrackJump_m() const { return max_track_jump_m_; }
  double maxWallPenetration_m() const { return max_wall_penetration_m_; }
  long lumenExitSteps() const { return lumen_exit_steps_; }
  const PhaseScore& total() const { return total_; }
  const PhaseScore& insertion() const { return insertion_; }
  const PhaseScore& withdrawal() const { return withdrawal_; }

 private:
  ScoreOptions o_;
  PhaseScore total_, insertion_, withdrawal_;
  std::optional<double> time_to_caecum_s_;
  std::optional<double> insertion_at_caecum_m_;
  double last_time_s_;
  long limited_steps_ = 0, limited_episodes_ = 0;
  double max_track_jump_m_ = 0, max_wall_penetration_m_ = 0;
  long lumen_exit_steps_ = 0;
  bool was_limited_ = false;
  bool have_prev_ = false;
  Telemetry prev_;
};

}  // namespace colosim
