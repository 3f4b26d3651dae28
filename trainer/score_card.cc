#include "trainer/score_card.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace colosim {

namespace {

// A metric compared with the expert: lower is better (forces, time in a loop...) or
// higher (lumen in view, mucosa seen).
struct RelativeMetric {
  const char* key;
  const char* label;
  const char* unit;
  bool lower_is_better;
  double slack;  // in the metric's unit: bands never narrower than this (an expert's 0)
};

// Green up to 1.25x the expert's value, amber up to 2x, red beyond: in the simulator
// studies that separated experts from novices, novices took 2.25-6x the expert's value
// (docs/trainer-window.md). `slack` keeps an expert's 0 from making every non-zero red.
constexpr double kGreenRatio = 1.25, kAmberRatio = 2.0;
// Higher is better (percentages): green within 10 points of the expert, amber within 25.
constexpr double kGreenPoints = 10.0, kAmberPoints = 25.0;

const RelativeMetric kRelative[] = {
    {"peak_push_N", "Peak push at the handle", "N", true, 2.0},
    {"peak_pull_N", "Peak pull at the handle", "N", true, 2.0},
    {"peak_handle_torque_Nm", "Peak handle torque", "N m", true, 0.01},
    {"high_force_time_pct", "Time above 10 N at the handle", "%", true, 2.0},
    {"peak_wall_force_N", "Peak wall force", "N", true, 2.0},
    {"excessive_pressure_episodes", "Excessive-pressure episodes", "", true, 1.0},
    {"discomfort_index", "Discomfort (colon stretched)", "s", true, 0.05},
    {"loop_time_s", "Time with a loop", "s", true, 1.0},
    {"max_loop_turns", "Largest loop", "turns", true, 0.25},
    {"redout_time_s", "Red-out (tip on the wall)", "s", true, 1.0},
    {"lumen_lost_count", "Lumen lost", "", true, 1.0},
    {"lumen_visible_pct", "Lumen in view", "%", false, 0.0},
    {"mucosa_visualised_pct", "Mucosa seen", "%", false, 0.0},
};

// Time to caecum (clinical): green below 16 min, amber to 20 min, red beyond.
constexpr double kCaecumGreen_s = 16 * 60.0, kCaecumAmber_s = 20 * 60.0;

std::optional<double> numberAt(const nlohmann::json& scores, const std::string& key) {
  if (!scores.is_object() || !scores.contains(key)) return std::nullopt;
  const nlohmann::json& v = scores.at(key);
  if (!v.is_number()) return std::nullopt;
  return v.get<double>();
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

std::vector<ScoreCardRow> scoreCard(const nlohmann::json& scores, const nlohmann::json* expert) {
  std::vector<ScoreCardRow> rows;
  const nlohmann::json none;
  const nlohmann::json& ref = expert ? *expert : none;
  const bool expert_reached = numberAt(ref, "time_to_caecum_s").has_value();

  // Caecum reached and the time it took: clinical thresholds, when reaching the caecum is
  // what the scenario's expert does (the sigmoid manoeuvres stop at the splenic flexure).
  const std::optional<double> t = numberAt(scores, "time_to_caecum_s");
  ScoreCardRow reached{"caecum_reached", "Caecum reached", "", t ? 1.0 : 0.0, std::nullopt, "none", ""};
  ScoreCardRow time{"time_to_caecum_s", "Time to caecum", "s", t, numberAt(ref, "time_to_caecum_s"), "none", ""};
  if (expert) reached.expert = expert_reached ? 1.0 : 0.0;
  if (expert_reached) {
    reached.band = t ? "green" : "red";
    reached.rule = "reached: green, not reached: red. Each session counts towards the caecal intubation rate, "
                   "whose minimum standard is 90 % (Rees et al., Gut 2016)";
    time.band = !t ? "red" : *t < kCaecumGreen_s ? "green" : *t < kCaecumAmber_s ? "amber" : "red";
    time.rule = "green < 16 min (caecal intubation time, quality threshold; Chak et al. 1996 propose a median "
                "< 15 min), amber 16-20 min (Lee et al. 2008: competence < 20 min), red beyond or not reached";
  } else {
    reached.rule = time.rule = "no band: the expert of this scenario does not go to the caecum";
  }
  rows.push_back(reached);
  rows.push_back(time);

  for (const RelativeMetric& m : kRelative) {
    ScoreCardRow r{m.key, m.label, m.unit, numberAt(scores, m.key), numberAt(ref, m.key), "none", ""};
    if (m.lower_is_better) {
      r.rule = "relative to the expert E: green <= max(1.25 E, E + " + fmt("%g", m.slack) + "), amber <= max(2 E, E + " +
               fmt("%g", 2 * m.slack) + "), red beyond";
      if (r.value && r.expert) {
        const double e = *r.expert;
        const double green = std::max(kGreenRatio * e, e + m.slack), amber = std::max(kAmberRatio * e, e + 2 * m.slack);
        r.band = *r.value <= green ? "green" : *r.value <= amber ? "amber" : "red";
      }
    } else {
      r.rule = "relative to the expert E: green >= E - 10 points, amber >= E - 25 points, red below";
      if (r.value && r.expert) {
        const double e = *r.expert;
        r.band = *r.value >= e - kGreenPoints ? "green" : *r.value >= e - kAmberPoints ? "amber" : "red";
      }
    }
    if (!expert) r.rule = "no band: no expert reference for this scenario";
    rows.push_back(r);
  }
  return rows;
}

std::string formatCardValue(const std::string& key, const std::optional<double>& value) {
  if (!value) return "-";
  if (key == "caecum_reached") return *value > 0.5 ? "yes" : "no";
  const double v = *value;
  if (key == "time_to_caecum_s") return fmt("%.1f", v) + " (" + fmt("%.1f", v / 60.0) + " min)";
  if (key == "excessive_pressure_episodes" || key == "lumen_lost_count") return fmt("%.0f", v);
  if (key == "peak_handle_torque_Nm") return fmt("%.3f", v);
  if (key == "max_loop_turns") return fmt("%.2f", v);
  return fmt("%.1f", v);
}

nlohmann::json scoreCardJson(const std::vector<ScoreCardRow>& rows) {
  nlohmann::json a = nlohmann::json::array();
  auto opt = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  for (const ScoreCardRow& r : rows)
    a.push_back({{"key", r.key},
                 {"label", r.label},
                 {"unit", r.unit},
                 {"value", opt(r.value)},
                 {"expert", opt(r.expert)},
                 {"band", r.band},
                 {"rule", r.rule},
                 {"shown", formatCardValue(r.key, r.value)},
                 {"expert_shown", formatCardValue(r.key, r.expert)}});
  return a;
}

}  // namespace colosim
