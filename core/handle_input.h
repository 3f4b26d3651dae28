// What the endoscopist does with the colonoscope's handle, sampled every step.
#pragma once

namespace colosim {

/// Handle inputs of one step. Ranges are enforced by the scope model (inputs outside
/// them are clamped there and refused by the file readers).
struct HandleInput {
  double insertion_m = 0.0;         ///< depth of the scope tip through the anus, along the scope [m], >= 0
  double rotation_rad = 0.0;        ///< axial rotation of the handle; positive is clockwise seen by the operator [rad]
  double knob_updown_rad = 0.0;     ///< up/down tip knob angle, positive is up, within +-pi [rad]
  double knob_leftright_rad = 0.0;  ///< left/right tip knob angle, positive is right, within +-160 deg [rad]
  /// Level of the scope's variable-stiffness section (ScopeParams::variable_stiffness), an
  /// index into its levels; -1 (files: the key left out) is the design's default level. A
  /// scope without such a section ignores it; a level past the last is the last.
  int stiffness_level = -1;
};

/// Largest knob angles [rad]: up/down 180 deg, left/right 160 deg (scope specifications).
constexpr double kKnobUpDownMax_rad = 3.14159265358979323846;
/// Most levels a variable-stiffness section may have (files refuse higher level indices).
constexpr int kStiffnessLevelsMax = 16;
constexpr double kKnobLeftRightMax_rad = 160.0 * 3.14159265358979323846 / 180.0;

}  // namespace colosim
