// Small scenarios and sessions for the trainer's tests, written into a TempDir.
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "fixture.h"
#include "trainer/strict_json.h"

namespace colosim::test {

/// A short scenario: dt 10 ms, 2.5 s, piecewise-constant inputs that change a few times
/// (so that its session is small: a few input lines, two checkpoints).
inline std::string smallScenarioText(const std::string& name = "small") {
  return R"({
  "format": "colosim-scenario", "version": 1, "name": ")" + name + R"(",
  "description": "test scenario",
  "anatomy": "anatomy/adult.json", "params": "params/default.json",
  "dt_s": 0.01, "duration_s": 2.5, "seed": 7,
  "start": {"kind": "rest"},
  "script": [
    {"t_s": 0.0,  "insertion_m": 0.0, "rotation_rad": 0.0, "knob_updown_rad": 0.0, "knob_leftright_rad": 0.0},
    {"t_s": 0.5,  "insertion_m": 0.0, "rotation_rad": 0.0, "knob_updown_rad": 0.0, "knob_leftright_rad": 0.0},
    {"t_s": 0.51, "insertion_m": 0.3, "rotation_rad": 0.5, "knob_updown_rad": 0.2, "knob_leftright_rad": -0.1},
    {"t_s": 1.2,  "insertion_m": 0.3, "rotation_rad": 0.5, "knob_updown_rad": 0.2, "knob_leftright_rad": -0.1},
    {"t_s": 1.21, "insertion_m": 0.9, "rotation_rad": 7.0, "knob_updown_rad": 1.2, "knob_leftright_rad": 0.3},
    {"t_s": 2.0,  "insertion_m": 0.9, "rotation_rad": 7.0, "knob_updown_rad": 1.2, "knob_leftright_rad": 0.3},
    {"t_s": 2.01, "insertion_m": 1.1, "rotation_rad": 7.0, "knob_updown_rad": 0.0, "knob_leftright_rad": 0.0}
  ]
})";
}

/// Expects an InputError whose message contains every fragment.
template <typename F>
void expectInputError(F&& f, std::initializer_list<std::string> fragments) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    for (const std::string& frag : fragments)
      EXPECT_NE(std::string(e.what()).find(frag), std::string::npos) << e.what() << "\n  lacks: " << frag;
  }
}

}  // namespace colosim::test
