// Tension law files (docs/identification.md, "Law files"): the law `colosim identify
// --law-out` writes and `colosim run --tension-law` loads for the colon's tension elements.
//
//   {
//     "format": "colosim-tension-law v1",
//     "law": "extended",                       // "voigt" when effects is empty
//     "effects": ["strain_stiffening"],        // names of core/extended_tension_law.h
//     "params": {"EA_N": {"value": 5.97, "unit": "N", "sd": 0.01}, ...},
//     "source": "colosim identify assets/measurements/....csv"
//   }
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/extended_tension_law.h"
#include "trainer/strict_json.h"

namespace colosim {

/// The JSON object of a law file (the format above); `sd` as for writeTensionLawFile. A
/// parameter file carries the same object as colon.tension_law (docs/file-formats.md).
nlohmann::json tensionLawJson(const ExtendedLawParams& law, const std::vector<double>& sd, const std::string& source);

/// Writes a law file (throws std::runtime_error when it cannot). `sd` gives optional
/// standard deviations by parameter name (same order as parameters(); may be empty).
void writeTensionLawFile(const std::string& path, const ExtendedLawParams& law, const std::vector<double>& sd,
                         const std::string& source);

/// Reads a law file strictly: unknown or missing keys, wrong units, unknown effects,
/// out-of-range values are InputError naming the file and key.
ExtendedLawParams readTensionLawFile(const std::string& path);
/// The same from the file's text in memory; `file` names it in messages.
ExtendedLawParams parseTensionLawFile(const std::string& text, const std::string& file);
/// The same from a law object being read (a law file's top level, or colon.tension_law of a
/// parameter file): reads every key and finishes the object.
ExtendedLawParams readTensionLawObject(JsonObject& law);

/// The law of a file, ready for buildColonModel.
std::shared_ptr<const TensionLaw> loadTensionLaw(const std::string& path);

}  // namespace colosim
