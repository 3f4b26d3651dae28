// Replaying a recorded insertion through the simulator (core/world.h through
// trainer/world_simulation.h) with a chosen set of model extensions.
#pragma once

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "core/extended_tension_law.h"
#include "identify/insertion/recording.h"
#include "trainer/assets.h"
#include "trainer/scenario.h"

namespace colosim {

/// Extension magnitudes of one simulated model; all zero is the paper's model (no wall
/// friction, no bending resistance, linear lifters, Voigt tension).
struct OrganParams {
  double friction = 0;             ///< wall_friction: Coulomb mu scope-mucosa [-]
  double bending_EI_Nm2 = 0;       ///< colon_bending: EI [N m^2]
  double stiffening_per_m2 = 0;    ///< mesentery_stiffening: beta [1/m^2]
  double fung_b = 0;               ///< strain_stiffening: Fung b [-]
  double relax_g1 = 0;             ///< stress_relaxation: g1 [-] (tau1 = kRelaxTau_s)
  double soften_d_inf = 0;         ///< cyclic_softening: d_inf [-] (a_c = kSoftenAc)
  double set_ratio = 0;            ///< permanent_set: r [-]
};
/// Relaxation time of the organ-level stress_relaxation candidate [s] (fixed: an insertion
/// of seconds cannot separate g1 from tau1).
constexpr double kRelaxTau_s = 2.0;
/// Characteristic accumulated loading strain of the organ-level cyclic_softening candidate
/// [-] (fixed, as tau1: one recording cannot separate d_inf from a_c; the value is of the
/// order of the loading strain the colon's elements accumulate in seconds of insertion,
/// docs/organ-identification.md).
constexpr double kSoftenAc = 0.1;

/// The candidate effects, in output order.
const std::vector<std::string>& organEffectNames();
/// The index of an effect in organEffectNames(), -1 for a name that is not one.
int organEffectIndex(const std::string& effect);
/// The magnitude of an effect in `p` (friction, EI, beta, b, g1, d_inf or r) and its setter.
double organEffectValue(const OrganParams& p, const std::string& effect);
void setOrganEffect(OrganParams& p, const std::string& effect, double value);
/// Parameter name and unit of each effect's magnitude (e.g. "friction_coefficient", "1").
std::pair<std::string, std::string> organEffectParameter(const std::string& effect);

/// What a replay needs besides the extensions: the scenario, its parameters with the
/// scenario's overrides, and the resolution.
struct ReplaySetup {
  Scenario scenario;
  Parameters params;
  double dt_s = 1e-3;
  /// After threading, the world runs this long with the handle held before the recording's
  /// clock starts (StartSpec::relax_s) [s]; < 0: the start specification's own.
  double relax_s = -1;
};
/// The scenario a recording names, with the parameter file it names (header key `params`,
/// as colosim run --params replaces the scenario's: useParameterFile); InputError naming
/// the recording for a scenario or parameter file that cannot be found.
Scenario recordingScenario(const InsertionRecording& rec);

/// Loads the scenario's parameters with its overrides (scenarioParameters); spacing_m > 0 replaces the colon's control-point
/// spacing and the scope's segment length (a coarser model for the search).
ReplaySetup makeReplaySetup(const Scenario& scenario, double spacing_m = 0);

/// The extended tension law of an extension set, with the parameters' EA and EC (empty when
/// no tension-law effect is on: the parameters' Voigt law).
std::optional<ExtendedLawParams> organLawParams(const Parameters& params, const OrganParams& p);
/// The parameter set of an extension set: friction, bending, stiffening and the tension law
/// (Parameters::tension_law, the parameters' own replaced) of `p`. A world built from it
/// (loadWorldModel with no law) is the model `replayInsertion` simulates.
Parameters organParameters(const Parameters& params, const OrganParams& p);

/// The simulator's answer at each row of a recording.
struct Prediction {
  std::vector<double> force_N, torque_Nm;  ///< handle force and torque [N], [N m]
  std::vector<Vec3> tip_m;                 ///< tip position [m]
  std::vector<double> loop_turns;          ///< telemetry loop measure [turns]
  bool ok = true;                          ///< false when a solve failed or a value is not finite
};

/// Replays the recorded inputs through the simulation `colosim run` builds for the scenario
/// (its start state with the scope threaded to the first row's input; a scripted start's
/// set-up is part of the recording), then one step of dt at a time, step s taking the input
/// interpolated at its end time s dt; each row takes the telemetry of the first step ending
/// at or after its time (row 0 at time 0: the start state). When `cancel` is set (checked
/// every step), it stops there and returns a prediction that is not ok.
Prediction replayInsertion(const ReplaySetup& setup, const InsertionRecording& rec, const OrganParams& p,
                           const std::atomic<bool>* cancel = nullptr);

}  // namespace colosim
