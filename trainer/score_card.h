// The trainer's score card (colosim train, at the end of a session): each metric of the
// session's scores with its unit, the expert reference of the scenario and a green / amber
// / red band. Pure data, no GL: the window draws the rows, tests check them.
// Bands and their sources: docs/trainer-window.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace colosim {

/// The scores of a scripted expert run, the reference the card compares a session with.
struct ExpertReference {
  std::string scenario;  ///< the scenario it is the reference for
  std::string expert;    ///< the shipped scenario whose scripted run made it
  std::string command;   ///< how the scores were made (colosim run EXPERT --score --json)
  nlohmann::json scores; ///< Scorer::json() of that run (an object)
};

/// assets/experts/references.json.
std::string expertReferencesPath();
/// Reads an expert references file strictly (format colosim-expert-references, version 1;
/// docs/file-formats.md): InputError naming the file and key.
std::vector<ExpertReference> loadExpertReferences(const std::string& path);
/// The reference for `scenario_name`, or nullptr.
const ExpertReference* findExpertReference(const std::vector<ExpertReference>& references,
                                           const std::string& scenario_name);

/// One line of the card.
struct ScoreCardRow {
  std::string key;                ///< the score key (Scorer::json), or "caecum_reached"
  std::string label;              ///< for people
  std::string unit;               ///< as displayed ("" for yes/no)
  std::optional<double> value;    ///< the session's (empty: not measured or not reached)
  std::optional<double> expert;   ///< the expert reference's (empty: none)
  std::string band;               ///< "green", "amber", "red" or "none" (no threshold applies)
  std::string rule;               ///< the thresholds in words, with their source
};

/// The card of a session's scores (Scorer::json of the whole session) against an expert
/// reference (nullptr: none; every relative band is then "none").
std::vector<ScoreCardRow> scoreCard(const nlohmann::json& scores, const ExpertReference* expert);
/// A value as the card shows it in `unit` ("-" when empty; "yes"/"no" for caecum_reached).
std::string formatCardValue(const std::string& key, const std::optional<double>& value);
/// The card as JSON (colosim train --json, "score_card"): one object per row with the keys
/// key, label, unit, value, expert, band, rule, shown (the value as displayed).
nlohmann::json scoreCardJson(const std::vector<ScoreCardRow>& rows);

}  // namespace colosim
