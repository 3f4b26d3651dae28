// Do the scores separate skill? (issue 21, "scores that separate skill")
//   trainer_skill_family [--members N] [--seed S] [--scenario NAME]... [--json]
// From the start of each scenario given (default sigmoid_untwist; sigmoid_push starts from
// the same alpha loop and scores from the same 2 s, so its family is the same), runs a family of N expert-like and N novice-like scripted sessions, the
// same intent with perturbed timing, depth and rotation, drawn from the seed:
//   expert: from 2 s, withdraw 12-18 cm over 6-10 s while turning 1.0-1.5 turns the way the
//           shipped expert untwist turns (sigmoid_untwist's script: anticlockwise, for its
//           reverse alpha loop),
//           hold 1.5-2.5 s, then advance 10-14 cm with the rotation held to the end (28 s),
//           steering the tip at the lumen with the knobs throughout, as the shipped expert
//           untwist does (runWithLumenSteering, trainer/lumen_following.h);
//   novice: from 2 s, push on 20-30 cm to the end, turning at most +-0.25 turn at random.
// Each session is scored as `colosim run` scores it (the scenario's scoring, from 2 s).
// Printed: every session's loop_time_s, peak_handle_force_N, discomfort_index,
// discomfort_time_pct, redout_time_s and lumen_visible_pct, and for the first three whether
// they separate the groups: every expert better (lower) than every novice. --json prints
// the same as one object. Deterministic: the same seed gives the same sessions and scores.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "trainer/lumen_following.h"
#include "trainer/replay.h"
#include "trainer/scenario.h"
#include "trainer/score.h"
#include "trainer/world_simulation.h"

using namespace colosim;

namespace {

constexpr double kTurn_rad = 6.283185307179586;

struct Member {
  std::string group;  // "expert" or "novice"
  std::vector<Keyframe> script;
  nlohmann::json scores;
};

Keyframe frame(double t_s, double insertion_m, double rotation_rad) {
  Keyframe k;
  k.t_s = t_s;
  k.input.insertion_m = insertion_m;
  k.input.rotation_rad = rotation_rad;
  return k;
}

// The scenario's start (its first keyframes up to the scored start, unchanged) and then one
// member's manoeuvre. u() draws uniformly in [0, 1).
template <class Uniform>
std::vector<Keyframe> expertScript(const Scenario& sc, double start_s, double end_s, double way, Uniform& u) {
  const double depth0_m = scriptedInput(sc.script, start_s).insertion_m;
  const double withdraw_m = 0.12 + 0.06 * u(), withdraw_s = 6 + 4 * u();
  const double turns = 1.0 + 0.5 * u(), hold_s = 1.5 + u(), advance_m = 0.10 + 0.04 * u();
  const double out_m = depth0_m - withdraw_m, rot_rad = way * turns * kTurn_rad;
  return {frame(0, depth0_m, 0), frame(start_s, depth0_m, 0), frame(start_s + withdraw_s, out_m, rot_rad),
          frame(start_s + withdraw_s + hold_s, out_m, rot_rad), frame(end_s, out_m + advance_m, rot_rad)};
}

template <class Uniform>
std::vector<Keyframe> noviceScript(const Scenario& sc, double start_s, double end_s, Uniform& u) {
  const double depth0_m = scriptedInput(sc.script, start_s).insertion_m;
  const double push_m = 0.20 + 0.10 * u(), twist_rad = (u() - 0.5) * 0.5 * kTurn_rad;
  const double mid_s = start_s + (end_s - start_s) * (0.4 + 0.2 * u());
  return {frame(0, depth0_m, 0), frame(start_s, depth0_m, 0), frame(mid_s, depth0_m + 0.5 * push_m, twist_rad),
          frame(end_s, depth0_m + push_m, twist_rad)};
}

// Scored as `colosim run` scores it; a steering member's knobs are decided as it runs
// (its script then holds them).
nlohmann::json run(Scenario sc, std::vector<Keyframe>& script, bool steer, double from_s) {
  sc.script = script;
  WorldSimulation sim(sc);
  Scorer scorer(sc.scoring);
  if (steer) {
    runWithLumenSteering(sc, sim, from_s, 0.5, 0.05, 0.4, [&](const WorldSimulation& s) { scorer.add(s.telemetry()); });
    script = sc.script;
  } else {
    for (long k = 0; k < sc.steps(); ++k) stepAndRecord(sim, scriptedInput(sc.script, k * sc.dt_s), k, scorer, nullptr);
  }
  return scorer.json();
}

double number(const nlohmann::json& j) { return j.is_number() ? j.get<double>() : NAN; }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Scripted expert-like and novice-like sessions from each sigmoid scenario's start, and whether the scores separate them"};
  int members = 5;
  unsigned seed = 1;
  std::vector<std::string> scenarios{"sigmoid_untwist"};
  bool json = false;
  app.add_option("--members", members, "sessions per group and scenario")->check(CLI::Range(1, 100));
  app.add_option("--seed", seed, "seed of the perturbations");
  app.add_option("--scenario", scenarios, "scenario whose start a family starts from (repeatable; default sigmoid_untwist)");
  app.add_flag("--json", json, "print one JSON object");
  CLI11_PARSE(app, argc, argv);

  const std::vector<std::string> keys{"loop_time_s", "peak_handle_force_N", "discomfort_index"};
  const std::vector<std::string> shown{"loop_time_s",         "peak_handle_force_N", "discomfort_index",
                                       "discomfort_time_pct", "redout_time_s",       "lumen_visible_pct"};
  nlohmann::json out{{"seed", seed}, {"members", members}, {"scenarios", nlohmann::json::object()}};
  // The way the shipped expert untwist turns by its end: +1 clockwise, -1 anticlockwise.
  const Scenario untwist = findScenario("sigmoid_untwist");
  const double way = scriptedInput(untwist.script, untwist.duration_s).rotation_rad < 0 ? -1.0 : 1.0;
  for (const std::string& name : scenarios) {
    const Scenario sc = findScenario(name);
    const double start_s = sc.scoring.start_s, end_s = sc.duration_s;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    auto u = [&] { return uniform(rng); };
    std::vector<Member> family;
    for (int i = 0; i < members; ++i) family.push_back({"expert", expertScript(sc, start_s, end_s, way, u), {}});
    for (int i = 0; i < members; ++i) family.push_back({"novice", noviceScript(sc, start_s, end_s, u), {}});
    nlohmann::json sessions = nlohmann::json::array();
    if (!json) {
      std::printf("%s (scored from %.1f s):\n  %-7s", name.c_str(), start_s, "group");
      for (const std::string& k : shown) std::printf(" %20s", k.c_str());
      std::printf("\n");
    }
    for (Member& m : family) {
      m.scores = run(sc, m.script, m.group == "expert", start_s);
      nlohmann::json s{{"group", m.group}, {"script", nlohmann::json::array()}};
      for (const Keyframe& k : m.script)
        s["script"].push_back({{"t_s", k.t_s}, {"insertion_m", k.input.insertion_m}, {"rotation_rad", k.input.rotation_rad}});
      for (const std::string& k : shown) s[k] = m.scores.at(k);
      sessions.push_back(s);
      if (!json) {
        std::printf("  %-7s", m.group.c_str());
        for (const std::string& k : shown) std::printf(" %20.4g", number(m.scores.at(k)));
        std::printf("\n");
      }
    }
    nlohmann::json separates = nlohmann::json::object();
    for (const std::string& k : keys) {
      double worst_expert = -INFINITY, best_novice = INFINITY;
      for (const Member& m : family) {
        const double v = number(m.scores.at(k));
        if (m.group == "expert") worst_expert = std::max(worst_expert, std::isnan(v) ? INFINITY : v);
        else best_novice = std::min(best_novice, std::isnan(v) ? -INFINITY : v);
      }
      separates[k] = {{"separates", worst_expert < best_novice}, {"worst_expert", worst_expert}, {"best_novice", best_novice}};
      if (!json)
        std::printf("  %-20s %s (worst expert %.4g, best novice %.4g)\n", k.c_str(),
                    worst_expert < best_novice ? "separates" : "does NOT separate", worst_expert, best_novice);
    }
    out["scenarios"][name] = {{"sessions", sessions}, {"separation", separates}};
  }
  if (json) std::printf("%s\n", out.dump(1).c_str());
  return 0;
}
