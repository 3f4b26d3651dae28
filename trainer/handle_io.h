// Handle inputs in files (scenario keyframes, session input lines): ranges and strict
// reading, shared so that every file accepts exactly the same inputs.
#pragma once

#include <nlohmann/json.hpp>

#include "core/handle_input.h"
#include "trainer/strict_json.h"

namespace colosim {

/// Deepest insertion a file may ask for [m]: a colonoscope's working length is ~1.6-1.7 m.
constexpr double kInsertionMax_m = 2.0;
/// Largest |rotation| a file may hold [rad] (~160 000 turns: an hour at 10 turns/s with
/// room to spare). Rotation is cumulative (the handle can turn many times); the bound only
/// catches garbage and wrong units.
constexpr double kRotationMax_rad = 1.0e6;

/// Reads the four handle keys (insertion_m, rotation_rad, knob_updown_rad,
/// knob_leftright_rad) of `obj`: each required, finite and within range
/// (insertion [0, 2] m, knobs within +-180 / +-160 deg), and the optional stiffness_level
/// (an integer 0-15; left out: -1, the scope design's default level). InputError otherwise.
HandleInput readHandleInput(JsonObject& obj);

/// Writes the four handle keys into a JSON object (doubles round-trip exactly), and
/// stiffness_level when it is not the default (-1): files without it read as before.
void writeHandleInput(nlohmann::json& obj, const HandleInput& in);

/// True when the two inputs are bit-for-bit the same values.
bool sameInput(const HandleInput& a, const HandleInput& b);

}  // namespace colosim
