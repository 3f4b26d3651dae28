// colosim score SESSION... [--json] [--threads N] [--report DIR]: replays sessions headless
// and scores them, on every core when given many; results in the order given; --report
// writes HTML pages of them (trainer/session_report.h).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "app/commands.h"
#include "trainer/progress.h"
#include "trainer/replay.h"
#include "trainer/session_report.h"
#include "trainer/strict_json.h"
#include "trainer/world_simulation.h"

namespace colosim::app {

namespace {

struct ScoreCommandOptions {
  std::vector<std::string> sessions;
  bool json = false;
  unsigned threads = 0;
  std::string report;  // a new or empty folder
};

// One session's line in the output: where it came from, how faithful the replay was,
// then the scores.
nlohmann::json sessionJson(const ReplayResult& r) {
  nlohmann::json j;
  j["session"] = r.file;
  j["scenario"] = r.scenario;
  j["steps"] = r.steps;
  j["complete"] = r.complete;
  j["truncated"] = r.truncated;
  if (r.truncated) j["message"] = r.message;
  j["state_hash_reproduced"] = r.hashOk();
  for (auto it = r.scores.begin(); it != r.scores.end(); ++it) j[it.key()] = it.value();
  return j;
}

std::string num(const nlohmann::json& v, const char* fmt) {
  if (v.is_null()) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v.get<double>());
  return buf;
}

int runScore(const ScoreCommandOptions& o) {
  // replaySessions reads every session first: a bad one stops the batch before any work;
  // the report folder and the expert sessions are checked before it too.
  std::vector<ExpertSession> experts;
  std::unique_ptr<ReportCollector> report;
  if (!o.report.empty()) {
    checkReportDir(o.report);
    experts = loadExpertSessions();
    report = std::make_unique<ReportCollector>(o.sessions.size(), experts);
  }
  constexpr long kBarUnits = 1000;
  ProgressBar bar(o.report.empty() ? "score" : "score + report", kBarUnits, stderrIsTerminal() && !o.json);
  const std::vector<ReplayResult> results =
      replaySessions(o.sessions, makeWorldSimulation, o.threads,
                     [&](long done, long total) { bar.update(done * kBarUnits / std::max(total, 1L)); },
                     report ? report->hooks() : SessionHooksFactory());
  bar.finish();
  nlohmann::json all = nlohmann::json::array();
  for (size_t i = 0; i < results.size(); ++i) {
    const ReplayResult& r = results[i];
    for (const std::string& w : r.warnings) std::cerr << "colosim: warning: " << w << "\n";
    if (r.truncated) std::cerr << "colosim: warning: " << r.message << "\n";
    if (!r.hashOk()) std::cerr << "colosim: warning: replay differs from the recording: " << r.mismatch << "\n";
    all.push_back(sessionJson(r));
  }
  if (report) {
    std::vector<SessionReportEntry> entries = report->takeEntries();
    for (size_t i = 0; i < entries.size(); ++i) entries[i].scores = all[i];
    writeSessionReport(o.report, entries, experts);
  }
  if (o.json) {
    std::cout << all.dump(2) << "\n";
    return 0;
  }
  for (const nlohmann::json& j : all) {
    std::cout << j["session"].get<std::string>() << " (" << j["scenario"].get<std::string>() << ", "
              << num(j["duration_s"], "%.1f") << " s" << (j["truncated"].get<bool>() ? ", TRUNCATED" : "") << ")\n";
    std::cout << "  time to caecum          " << num(j["time_to_caecum_s"], "%.1f") << " s\n"
              << "  peak handle force       " << num(j["peak_handle_force_N"], "%.1f") << " N\n"
              << "  peak wall force         " << num(j["peak_wall_force_N"], "%.1f") << " N, "
              << j["excessive_pressure_episodes"].get<int>() << " excessive-pressure episodes\n"
              << "  discomfort              index " << num(j["discomfort_index"], "%.2f") << " s, "
              << num(j["discomfort_time_pct"], "%.1f") << " % of the time\n"
              << "  loops                   " << num(j["loop_time_s"], "%.1f") << " s with a loop, largest "
              << num(j["max_loop_turns"], "%.2f") << " turns, writhe " << num(j["loop_writhe_max"], "%.2f")
              << " turns\n";
    std::cout << "  shortest region         ";
    const char* sep = "";
    for (const auto& [region, ratio] : j["region_length_ratio_min"].items())
      std::cout << sep << region << " " << num(ratio, "%.2f"), sep = ", ";
    std::cout << " of rest length\n"
              << "  mucosa visualised       " << num(j["mucosa_visualised_pct"], "%.1f") << " %\n"
              << "  red-out                 " << num(j["redout_time_s"], "%.1f") << " s, lumen lost "
              << j["lumen_lost_count"].get<int>() << " times\n";
  }
  if (report) std::cout << "Report written to " << o.report << "/index.html\n";
  return 0;
}

}  // namespace

void addScoreCommand(CLI::App& app, Action& action) {
  auto o = std::make_shared<ScoreCommandOptions>();
  CLI::App* cmd = app.add_subcommand("score", "Replay recorded sessions headless and score them (every core when given many)");
  cmd->add_option("SESSION", o->sessions, "session files (.jsonl)")->required();
  cmd->add_flag("--json", o->json, "print a JSON array, one object per session in the order given");
  cmd->add_option("--threads", o->threads, "worker threads (0: every core)")->check(CLI::Range(0u, 1024u))
      ->capture_default_str();
  cmd->add_option("--report", o->report, "write HTML pages into this new or empty folder: per session the timelines "
                  "with the events marked and the global view at a few moments; the cohort against the expert "
                  "sessions (gnuplot plots, nothing fetched from the network)");
  cmd->callback([&action, o] { action = [o]() -> int { return runScore(*o); }; });
}

}  // namespace colosim::app
