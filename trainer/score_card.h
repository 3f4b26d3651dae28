// The trainer's score card (colosim train, at the end of a session): each metric of the
// session's scores with its unit, the expert reference of the scenario (the scores of its
// shipped expert session, assets/sessions/expert/) and a green / amber / red band. Pure
// data, no GL: the window draws the rows, tests check them.
// Bands and their sources: docs/trainer-window.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace colosim {

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

/// The card of a session's scores (Scorer::json of the whole session) against the scores
/// of the scenario's expert session (trainer/expert_sessions.h: expertFor(...)->scores;
/// nullptr: none, and every relative band is then "none").
std::vector<ScoreCardRow> scoreCard(const nlohmann::json& scores, const nlohmann::json* expert_scores);
/// A value as the card shows it in `unit` ("-" when empty; "yes"/"no" for caecum_reached).
std::string formatCardValue(const std::string& key, const std::optional<double>& value);
/// The card as JSON (colosim train --json, "score_card"): one object per row with the keys
/// key, label, unit, value, expert, band, rule, shown (the value as displayed).
nlohmann::json scoreCardJson(const std::vector<ScoreCardRow>& rows);

}  // namespace colosim
