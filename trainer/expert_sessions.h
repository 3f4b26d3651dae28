// The shipped expert sessions (assets/sessions/expert/): what a trainee's session is
// compared with in reports and score cards. Their scores are the ones their end lines
// recorded (the run that made them; replaying them reproduces the same state hashes
// while the simulation is unchanged, which tests/trainer/session_report_test.cc checks
// against the pinned hash of the scenario).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainer/scenario.h"

namespace colosim {

struct ExpertSession {
  std::string file;
  std::string scenario_id;  ///< as the session's header names it
  Scenario scenario;
  nlohmann::json scores;    ///< Scorer::json() of the recorded run (the end line's summary.scores)
};

/// Reads the header and end line (readSessionEnds) of every *.jsonl and *.jsonl.gz in
/// `dir` (default: assets/sessions/expert), in file-name order.
/// InputError naming the file for a bad session, one without its end line or without
/// scores in its summary. A missing folder gives none.
std::vector<ExpertSession> loadExpertSessions(const std::string& dir = "");

/// The expert session to compare a session of `scenario` with: one of the same scenario,
/// else one whose scenario has the same anatomy and start (the same manoeuvre from the
/// same state, e.g. sigmoid_push and sigmoid_untwist); nullptr when none. `why`, when
/// given, receives "same scenario" or "same start as SCENARIO".
const ExpertSession* expertFor(const Scenario& scenario, const std::vector<ExpertSession>& experts,
                               std::string* why = nullptr);

}  // namespace colosim
