// What the trainee asks of the team around the patient, besides the handle.
#pragma once

#include <string>

namespace colosim {

/// What the trainee asks of the team around the patient, besides the handle: an
/// assistant's hand pressing on the abdomen, and the patient turned to another position.
/// Recorded in sessions as assist lines (docs/file-formats.md, "Sessions") and applied
/// from the next step on, so replays reproduce it.
struct AssistInput {
  bool abdominal_pressure = false;  ///< an assistant presses on the abdomen
  /// left_lateral, right_lateral, supine or prone; empty: the position the run started in.
  std::string patient_position;
  bool operator==(const AssistInput& o) const {
    return abdominal_pressure == o.abdominal_pressure && patient_position == o.patient_position;
  }
  bool operator!=(const AssistInput& o) const { return !(*this == o); }
};

}  // namespace colosim
