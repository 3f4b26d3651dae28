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

#include "core/extended_tension_law.h"

namespace colosim {

/// Writes a law file (throws std::runtime_error when it cannot). `sd` gives optional
/// standard deviations by parameter name (same order as parameters(); may be empty).
void writeTensionLawFile(const std::string& path, const ExtendedLawParams& law, const std::vector<double>& sd,
                         const std::string& source);

/// Reads a law file strictly: unknown or missing keys, wrong units, unknown effects,
/// out-of-range values are InputError naming the file and key.
ExtendedLawParams readTensionLawFile(const std::string& path);
/// The same from the file's text in memory; `file` names it in messages.
ExtendedLawParams parseTensionLawFile(const std::string& text, const std::string& file);

/// The law of a file, ready for buildColonModel.
std::shared_ptr<const TensionLaw> loadTensionLaw(const std::string& path);

}  // namespace colosim
