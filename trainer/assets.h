// Loading colosim's asset files (parameters, anatomy) into core's plain structs.
// Formats: docs/file-formats.md. Every reader is strict (see strict_json.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/colon_model.h"
#include "core/extended_tension_law.h"
#include "core/contact.h"
#include "core/scope_model.h"
#include "core/world.h"

namespace colosim {

/// Everything in a parameter file (assets/params/*.json).
struct Parameters {
  ColonParams colon;
  ScopeParams scope;
  ContactParams contact;
  /// The colon's tension law when it is not the Voigt law of colon.tension_EA_N / EC_Ns
  /// (colon.tension_law in the file, written by `colosim identify --law-out` on a recorded
  /// insertion; its EA and EC are those of the parameter set). Empty: the Voigt law.
  std::optional<ExtendedLawParams> tension_law;
  std::string file;       ///< where it was read from
  uint64_t hash = 0;      ///< FNV-1a of the file's bytes: names the parameter set in sessions
};

/// Reads a parameter file; throws InputError naming the file and key.
Parameters loadParameters(const std::string& path);
/// The same from the file's text in memory (loadParameters reads the file and calls it);
/// `file` names it in messages and in Parameters::file.
Parameters parseParameters(const std::string& text, const std::string& file);

/// Reads an anatomy file (assets/anatomy/*.json); throws InputError naming the file and key.
Anatomy loadAnatomy(const std::string& path);
/// The same from the file's text in memory; `file` names it in messages.
Anatomy parseAnatomy(const std::string& text, const std::string& file);

/// The folder of the shipped assets: $COLOSIM_ASSETS when set, else the source tree's
/// assets/ folder this build was configured from.
std::string assetDir();
/// A shipped asset by its path relative to the asset folder, e.g. "params/default.json".
std::string assetPath(const std::string& relative);

/// FNV-1a of a file's bytes (0 when it cannot be read).
uint64_t hashFile(const std::string& path);
/// FNV-1a of bytes in memory (hashFile of a file holding them).
uint64_t hashBytes(const std::string& bytes);

}  // namespace colosim

namespace colosim {
/// Builds the colon model of an anatomy file with a parameter set; a mismatch between
/// the two (an unknown mesentery class, repeated waypoints) is an InputError naming the
/// anatomy file. The tension elements follow `law` when given, else the parameters' law
/// (Parameters::tension_law, else their Voigt law).
ColonModel loadColonModel(const std::string& anatomy_path, const Parameters& params,
                          std::shared_ptr<const TensionLaw> law = nullptr);
/// The colon model of an anatomy already read from `anatomy_file` (loadColonModel without
/// the reading): the same InputError naming the anatomy file on a mismatch.
ColonModel colonModelOf(const Anatomy& anatomy, const std::string& anatomy_file, const Parameters& params,
                        std::shared_ptr<const TensionLaw> law = nullptr);
/// The world (colon, scope at its anus, contacts) of an anatomy file with a parameter set.
WorldModel loadWorldModel(const std::string& anatomy_path, const Parameters& params,
                          std::shared_ptr<const TensionLaw> law = nullptr);
}  // namespace colosim
