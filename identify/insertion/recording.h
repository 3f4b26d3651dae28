// Recorded insertions (issue 7; docs/organ-identification.md): the measurement format of
// the tension identification (identify/measurement.h) with `# experiment: insertion`,
// `# scenario: NAME` and the columns
//   time_s,insertion_m,rotation_rad,knob_updown_rad,knob_leftright_rad,handle_force_N,handle_torque_Nm
// optionally followed by tip_x_m,tip_y_m,tip_z_m (a tracked tip, in the scenario's frame),
// or the columns of `colosim run --trace` (insertionTraceColumns). An optional header key
// `params` names the parameter file the recording was simulated with (colosim run --params).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/handle_input.h"
#include "core/spline.h"

namespace colosim {

struct InsertionRecording {
  std::string file;
  std::vector<std::pair<std::string, std::string>> metadata;  ///< header keys in file order
  std::string scenario;                 ///< colosim scenario the bench reproduces
  std::string params;                   ///< parameter file replacing the scenario's ("": none)
  std::vector<double> time_s;           ///< [s], strictly increasing
  std::vector<HandleInput> input;       ///< handle inputs per row
  std::vector<double> force_N;          ///< measured axial handle force, + = push [N]
  std::vector<double> torque_Nm;        ///< measured axial handle torque [N m]
  bool has_tip = false;
  std::vector<Vec3> tip_m;              ///< tracked tip [m] (when has_tip)
  size_t rows() const { return time_s.size(); }
};

constexpr size_t kMinInsertionRows = 36;

/// The column names, without and with the tip.
std::vector<std::string> insertionColumns(bool with_tip);
/// The columns of `colosim run --trace`: those of a recording with the tip, then telemetry
/// the identification does not use (wall_force_peak_N, tip_to_caecum_m, tip_arclength_m,
/// mesentery_stretch, loop_turns). The reader accepts them.
std::vector<std::string> insertionTraceColumns();

/// Reads a recorded insertion; InputError "file:line: message" for a bad file (missing
/// header key, wrong columns, non-increasing time, NaN, too few rows, inputs out of range).
InsertionRecording readInsertionRecording(const std::string& path);

/// Writes a recording (header `experiment` and `scenario` first, then `metadata`).
void writeInsertionRecording(const std::string& path, const InsertionRecording& rec);

/// The value of the `# experiment:` header line of a measurement file ("" when absent);
/// InputError when the file cannot be read.
std::string measurementExperiment(const std::string& path);

/// The recorded input at time t_s: linear between rows, the first row before, the last after.
HandleInput recordedInput(const InsertionRecording& rec, double t_s);

}  // namespace colosim
