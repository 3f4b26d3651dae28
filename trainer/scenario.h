// Scenarios (assets/scenarios/*.json): a colon, a parameter set, a start state and the
// handle inputs of a scripted run as keyframes. Format: docs/file-formats.md ("Scenarios").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/handle_input.h"
#include "core/input_error.h"
#include "core/spline.h"
#include "trainer/assets.h"
#include "trainer/score.h"

namespace colosim {

/// Handle inputs at one time; inputs between keyframes are interpolated linearly.
struct Keyframe {
  double t_s = 0.0;  ///< [s], strictly increasing, the first at 0
  HandleInput input;
};

/// How the simulation starts.
struct ScenarioStart {
  /// "rest": colon in its rest shape, scope at the first keyframe's inputs;
  /// "settled": the colon first settles for settle_s under gravity, scope held at the
  ///   first keyframe (not recorded: part of building the simulation);
  /// "scripted": like "rest", but the script's first until_s seconds set the scene up
  ///   (for example forming the alpha loop): they are simulated and recorded, not scored.
  std::string kind = "rest";
  double settle_s = 0.0;  ///< [s], "settled" only
  double until_s = 0.0;   ///< [s], "scripted" only
  /// Optional, with any kind: one region of the colon starts displaced from its rest
  /// shape (for example a sigmoid rolled into an alpha loop), at rest, before the scope is
  /// threaded along the colon. Its control points are placed along the Catmull-Rom curve
  /// through shape_points_m at their rest arclength spacing, scaled to the curve's
  /// length; the curve must start and end within 1 cm of the region's end points at rest
  /// (the rest of the colon stays where it is). The mesentery still pulls the region
  /// back towards its rest shape: the start is a deformed state, not a new anatomy.
  std::string shape_region;           ///< a region name of the anatomy; empty: no shape
  std::vector<Vec3> shape_points_m;   ///< waypoints in the patient frame (at least 4) [m]
};

/// Parameter overrides for this scenario (unset: the parameter file's value).
struct ScenarioOverrides {
  std::optional<double> wall_friction;            ///< scope-mucosa friction coefficient [-] (default 0.1)
  std::optional<std::string> patient_position;    ///< left_lateral | right_lateral | supine | prone
  /// Axial rigidity EA of the colon's tension elements [N], instead of the parameter file's
  /// tension_stiffness_density x tension_reference_length^2 (the paper's reading, 28.9 N;
  /// a whole-tube value is 460-880 N: docs/parameters.md).
  std::optional<double> colon_axial_rigidity_N;
};

/// Abdominal pressure (core/abdominal_pressure.h): an assistant's hand pressing on the
/// abdomen over one region of the colon during [from_s, to_s] of the session's clock,
/// modelled as extra lifters of these densities on the region, ramped in and out over
/// ramp_s. Read from the scenario only, so replays reproduce it.
struct AbdominalPressure {
  std::string region;               ///< a region name of the anatomy (checked when the simulation is built)
  double from_s = 0.0;              ///< [s]
  double to_s = 0.0;                ///< [s], > from_s
  double ramp_s = 1.0;              ///< [s], linear ramp in and out (default 1 s)
  double stiffness_N_per_m2 = 0.0;  ///< k [N/m per m]
  double damping_Ns_per_m2 = 0.0;   ///< c [N s/m per m]
};

/// A change of the patient's position at a time of the script (a scripted manoeuvre; the
/// trainee's own turns are session assist lines): from the first step starting at or after
/// at_s, gravity turns about the body's long axis to `position`'s over
/// WorldSimulation::kTurnDuration_s, as for a trainee's call (WorldSimulation::assist).
struct PatientTurn {
  double at_s = 0.0;     ///< [s], strictly increasing along the list
  std::string position;  ///< left_lateral | right_lateral | supine | prone
};

struct Scenario {
  std::string name;
  std::string description;
  /// The manoeuvre's goal in a few sentences for the trainee (optional key "goal"; the
  /// trainer's start screen shows it, or the description when it is empty).
  std::string goal;
  std::string file;           ///< where it was read from
  uint64_t file_hash = 0;     ///< FNV-1a of the file's bytes
  /// How a session names it: the name for a shipped scenario (found again in
  /// assets/scenarios/), the absolute path otherwise.
  std::string id;
  std::string anatomy_path;   ///< resolved path of the anatomy file
  std::string params_path;    ///< resolved path of the parameter file
  /// params_path is not the file the scenario names but one given for the run
  /// (useParameterFile); sessions then record it.
  bool params_replaced = false;
  /// Resolved path of the scope design (trainer/scope_design.h; key "scope", default
  /// scopes/standard.json).
  std::string scope_path;
  /// scope_path is not the design the scenario names but one given for the run
  /// (useScopeDesign: a design study, `colosim run --scope`); sessions then record it.
  bool scope_replaced = false;
  /// overrides.patient_position is the trainee's choice (choosePatientPosition), not the
  /// file's; sessions then record it.
  bool patient_position_chosen = false;
  double dt_s = 1e-3;         ///< time step [s]
  double duration_s = 0.0;    ///< length of the scripted run [s]
  int seed = 0;               ///< seed of every random choice of the simulation
  ScenarioStart start;
  ScenarioOverrides overrides;
  ScoreOptions scoring;       ///< thresholds (defaults unless the file sets them)
  std::vector<AbdominalPressure> abdominal_pressure;  ///< optional, in file order
  std::vector<PatientTurn> patient_turns;             ///< optional, in time order
  std::vector<Keyframe> script;

  /// Number of steps of the scripted run: round(duration_s / dt_s).
  long steps() const;
};

/// Reads a scenario file strictly: InputError naming the file, the key path and its line.
Scenario loadScenario(const std::string& path);
/// The same from the file's text in memory (`file` names it in messages), except Scenario::id,
/// which depends on where the file is: loadScenario reads the file, calls this and sets it.
Scenario parseScenario(const std::string& text, const std::string& file);

/// SCENARIO as users give it: an existing file, or the name of a file in
/// assets/scenarios/ (with or without ".json"), else in assets/scenarios/bench/ (the
/// identification bench's specimens). InputError listing the shipped names when none exists.
std::string resolveScenarioPath(const std::string& name_or_path);
/// resolveScenarioPath then loadScenario.
Scenario findScenario(const std::string& name_or_path);
/// Names of the shipped training scenarios (assets/scenarios/*.json), sorted.
std::vector<std::string> shippedScenarioNames();

/// An error found in a scenario after it was read ("FILE: key.path: what"), with the line
/// of its key in the scenario file added when the file still has it.
InputError scenarioError(const std::string& file, const std::string& message);

/// The parameters a scenario runs with: its parameter file, its scope design
/// (trainer/scope_design.h: the design's sheath friction unless the parameter file was
/// replaced) and its overrides applied (patient position, wall friction, colon axial
/// rigidity). InputError naming the
/// scenario's line when it overrides the EA of a parameter file that carries a tension law.
Parameters scenarioParameters(const Scenario& scenario);
/// Runs the scenario with another parameter file (`colosim run SCENARIO --params FILE`, e.g.
/// one written by `colosim identify --law-out`): the file states the wall friction and the
/// colon's axial rigidity to use, so the scenario's wall_friction and colon_axial_rigidity_N
/// overrides are dropped; the wall friction's value is returned (empty: none).
std::optional<double> useParameterFile(Scenario& scenario, const std::string& params_path);

/// Runs the scenario with another scope design (`colosim run SCENARIO --scope FILE`, a design
/// study): the path is made absolute and recorded in sessions. InputError when the file
/// cannot be read as a scope design.
void useScopeDesign(Scenario& scenario, const std::string& scope_path);

/// The patient positions a scenario can take (core/colon_model.h gravityForPosition).
const std::vector<std::string>& patientPositions();
/// The position a patient is turned to next, a quarter turn at a time about the body's long
/// axis: left lateral, supine, right lateral, prone, left lateral again. InputError for a
/// position not in patientPositions().
std::string nextPatientPosition(const std::string& position);
/// The patient position the scenario runs with: its override, else its parameter file's.
std::string patientPositionOf(const Scenario& scenario);
/// Runs the scenario with the patient in `position` (the trainer's start screen), recorded
/// in sessions (header key patient_position) so that replays use it. InputError for a
/// position not in patientPositions().
void choosePatientPosition(Scenario& scenario, const std::string& position);

/// The scripted handle input at time t_s: linear between keyframes, the first keyframe
/// before it, the last after it.
HandleInput scriptedInput(const std::vector<Keyframe>& script, double t_s);

}  // namespace colosim
