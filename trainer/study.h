// Design studies (assets/studies/*.json): scope designs x scenarios x driving strategies x
// seeds, every case run deterministically, the metrics summarised per design with a paired
// comparison against the first design. `colosim study` is a thin main over this.
// Formats: docs/file-formats.md ("Studies", "Study shards"); the seeds and the metrics'
// definitions: docs/design-studies.md.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/spline.h"
#include "trainer/scenario.h"

namespace colosim {

/// One scope design of a study.
struct StudyDesign {
  std::string name;
  std::string scope;  ///< scope design file as written (relative to assets/), "" for the scenario's own
  std::string scope_path;  ///< resolved path ("" when scope is "")
  /// Optional: the shaft's bending stiffness EI, uniform along the length [N m^2].
  std::optional<double> shaft_bending_stiffness_Nm2;
  /// Optional: the operator stiffens a variable-stiffness design to this level
  /// (HandleInput::stiffness_level) from stiffen_from_s of the scenario's clock on (in the
  /// scripted manoeuvre's time, before a seed's time-warp). Empty: the design's default level.
  std::optional<int> stiffness_level;
  double stiffen_from_s = 0.0;  ///< [s]
};

/// A driving strategy: "scripted" (the scenario's script) or "lumen_following" (the
/// controller of trainer/lumen_following.h drives from the scored start until end_s).
struct StudyStrategy {
  std::string kind;
  double end_s = 0.0;  ///< lumen_following: simulated time at which the run ends [s]
  std::string name() const { return kind; }
};

struct Study {
  std::string name;
  std::string description;
  std::string file;
  uint64_t file_hash = 0;  ///< FNV-1a of the study file's bytes: names the study in shards
  std::vector<StudyDesign> designs;
  std::vector<std::string> scenarios;  ///< as written: shipped names or paths
  std::vector<StudyStrategy> strategies;
  std::vector<int> seeds;
  /// Optional cap on every case's simulated time (tests, quick looks) [s]; 0: none.
  double duration_s = 0.0;
  /// Report: times at which the scope's shape is drawn [s].
  std::vector<double> shape_times_s;
};

/// One case of a study: indices into the study's lists.
struct StudyCase {
  int index = 0;  ///< position in the canonical order
  int design = 0, scenario = 0, strategy = 0, seed = 0;  ///< indices (seed: into Study::seeds)
};

/// Reads a study file strictly (InputError naming the file, the key path and its line).
/// Scenarios and scope files named are checked to exist.
Study loadStudy(const std::string& path);
Study parseStudy(const std::string& text, const std::string& file);

/// The cases in canonical order: design outermost, then scenario, strategy, seed.
std::vector<StudyCase> studyCases(const Study& study);

/// The names of the metrics, in output order (docs/design-studies.md).
const std::vector<std::string>& studyMetricNames();

/// What one case measured. A metric without a value (time_to_caecum_s when the caecum is
/// not reached) is empty.
struct CaseResult {
  int index = 0;
  std::vector<std::optional<double>> metrics;  ///< by studyMetricNames()
  long steps = 0;
  uint64_t final_state_hash = 0;
  // Report data (not in shards): sampled at kStudyTimelineHz.
  std::vector<double> time_s, wall_force_total_N, handle_force_N;
  /// Scope centreline at each Study::shape_times_s (empty when the case ends earlier) [m].
  std::vector<std::vector<Vec3>> shapes_m;
};

/// Timelines of a case are sampled this often [1/s].
constexpr double kStudyTimelineHz = 10.0;

/// A seed's patient and operator variant (docs/design-studies.md). Seed 0: all factors 1
/// (the scenario as shipped).
struct SeedVariant {
  double operator_speed = 1.0;     ///< script time-warp / controller speed factor [-]
  double lifter_stiffness = 1.0;   ///< factor on every mesentery class's stiffness [-]
  double wall_friction = 1.0;      ///< factor on the scope-mucosa friction coefficient [-]
};
SeedVariant seedVariant(int seed);

/// The scenario a case runs (design, seed and strategy applied; script time-warped).
Scenario caseScenario(const Study& study, const StudyCase& c);

/// Runs one case; `on_steps` is told of steps done (for progress), may be empty.
CaseResult runStudyCase(const Study& study, const StudyCase& c, const std::function<void(long)>& on_steps = {});

/// An estimate of a case's steps (for progress bars).
long caseSteps(const Study& study, const StudyCase& c);

/// Runs the given cases on `threads` threads (results in the order of `cases`, identical
/// whatever the thread count). `on_progress(done, total)` counts steps.
std::vector<CaseResult> runStudyCases(const Study& study, const std::vector<StudyCase>& cases, int threads,
                                      const std::function<void(long, long)>& on_progress = {});

/// Statistics (docs/design-studies.md).
struct MeanSd {
  std::optional<double> mean, sd;  ///< mean over the values; sd (n - 1) needs n >= 2
  int n = 0;
};
MeanSd meanSd(const std::vector<double>& values);
/// Two-sided 97.5 % quantile of Student's t with `dof` degrees of freedom (dof >= 1).
double studentT975(int dof);
/// Mean difference and its 95 % Student t interval (n - 1 dof); ci empty for n < 2.
struct PairedDifference {
  std::optional<double> mean_difference;
  std::optional<std::pair<double, double>> ci95;
  int n = 0;
};
PairedDifference pairedDifference(const std::vector<double>& differences);

/// What the summary needs: the study's name, design names, the case count, and for every
/// case its keys and metrics (all cases, in canonical order).
struct StudyResults {
  std::string study;
  uint64_t study_hash = 0;
  std::vector<std::string> designs;
  int scenarios = 0, strategies = 0, seeds = 0;
  std::vector<CaseResult> cases;  ///< indexed by case index
};

/// The --json summary (docs/file-formats.md, "colosim study --json").
nlohmann::ordered_json studySummaryJson(const StudyResults& r);
/// The text summary: per design each metric's mean and sd, and the paired comparison.
std::string studySummaryText(const StudyResults& r, const std::vector<std::string>& case_labels = {});

/// Shards: case index mod n == k - 1 belongs to shard k of n.
std::vector<StudyCase> shardCases(const std::vector<StudyCase>& all, int k, int n);
/// "K/N" -> (k, n); InputError unless 1 <= K <= N.
std::pair<int, int> parseShard(const std::string& text);
/// Writes DIR/shard-K-of-N.json (never overwrites; the folder is created when missing).
/// Returns the path written.
std::string writeShard(const Study& study, int k, int n, const std::vector<StudyCase>& cases,
                       const std::vector<CaseResult>& results, const std::string& dir);
/// Reads every shard file (shard-*.json) of the folders and checks that they come from one
/// study and hold every case exactly once: InputError naming the file otherwise.
StudyResults mergeShards(const std::vector<std::string>& dirs);

/// Results of a study run on one machine, as merge would give them.
StudyResults studyResults(const Study& study, std::vector<CaseResult> results);

/// Writes the report into `dir` (created when missing; only the report's own files are
/// written): data files, gnuplot scripts and, when gnuplot is found, PNGs. Returns lines
/// to tell the user (what was written, or why PNGs were skipped).
std::vector<std::string> writeStudyReport(const Study& study, const std::vector<StudyCase>& cases,
                                          const std::vector<CaseResult>& results, const std::string& dir);

}  // namespace colosim
