// Scope designs (assets/scopes/*.json): one colonoscope as built - its length, diameter,
// mass, stiffness along the insertion tube, steerable tip, knob stops, tip light and
// sheath - so that designs can be compared on the same patients (docs/design-studies.md).
// A scenario names its design (key "scope", default scopes/standard.json, today's scope).
// Format: docs/file-formats.md ("Scope designs").
//
// What a design sets and what stays with the parameter file: the design is the
// instrument; the parameter file keeps the simulation's numerics of it (segment length,
// joint penalty and damping, drag, interaction points, solver and grip limits) and the
// patient. The design's sheath friction replaces the parameter file's scope-mucosa
// friction, unless the run's parameter file was given in place of the scenario's
// (`colosim run --params`, an identified patient: its friction was measured with the scope
// it was recorded with); a scenario's own wall_friction override wins over both.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/scope_model.h"

namespace colosim {

struct ScopeDesign {
  std::string name;
  std::string description;
  std::string file;       ///< where it was read from
  uint64_t hash = 0;      ///< FNV-1a of the file's bytes
  double working_length_m = 1.6;          ///< [m]
  double outer_diameter_m = 0.0125;       ///< [m]
  double mass_per_length_kg_per_m = 0.2;  ///< [kg/m]
  /// EI and GJ along the insertion tube from the tip; the last section ends at the
  /// working length.
  std::vector<StiffnessSection> stiffness_profile;
  double bending_section_length_m = 0.09; ///< [m]
  double knob_updown_max_rad = kKnobUpDownMax_rad;      ///< [rad]
  double knob_leftright_max_rad = kKnobLeftRightMax_rad; ///< [rad]
  /// Optional "knob_moment_limit": ScopeParams::knob_moment_limit_Nm [N m].
  double knob_moment_limit_Nm = ScopeParams().knob_moment_limit_Nm;
  double tip_light_reach_m = 0.02;        ///< [m], ScopeParams::tip_light_reach_m
  double sheath_friction = 0.1;           ///< scope-mucosa Coulomb coefficient [-]
  /// Optional "active": actuated joints (core/active_scope.h); enabled false without it.
  ActiveScopeParams active;
  /// Optional "variable_stiffness": the operator-switched section; levels empty without it.
  VariableStiffnessParams variable_stiffness;
};

/// Reads a scope design strictly: InputError naming the file, the key and its line.
ScopeDesign loadScopeDesign(const std::string& path);
/// The same from the file's text in memory (`file` names it in messages).
ScopeDesign parseScopeDesign(const std::string& text, const std::string& file);

/// The scope of `params` built as `design` (the numerics of the simulation stay).
void applyScopeDesign(const ScopeDesign& design, ScopeParams& params);

/// The design a scenario runs with when it names none.
constexpr const char* kDefaultScopeDesign = "scopes/standard.json";

}  // namespace colosim
