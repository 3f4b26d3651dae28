#include "trainer/expert_sessions.h"

#include <algorithm>
#include <filesystem>

#include "trainer/assets.h"
#include "trainer/session.h"
#include "trainer/strict_json.h"

namespace colosim {

namespace {

// NAME.jsonl, or NAME.jsonl.gz (gzip-compressed: readSession reads both).
bool isSessionFileName(const std::filesystem::path& file) {
  return std::filesystem::path(withoutGzipSuffix(file.string())).extension() == ".jsonl";
}

bool sameStart(const Scenario& a, const Scenario& b) {
  const ScenarioStart &s = a.start, &t = b.start;
  return a.anatomy_path == b.anatomy_path && s.kind == t.kind && s.settle_s == t.settle_s &&
         s.until_s == t.until_s && s.shape_region == t.shape_region && s.shape_points_m == t.shape_points_m;
}

}  // namespace

std::vector<ExpertSession> loadExpertSessions(const std::string& dir_in) {
  namespace fs = std::filesystem;
  const std::string dir = dir_in.empty() ? assetPath("sessions/expert") : dir_in;
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return {};
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (isSessionFileName(e.path())) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  std::vector<ExpertSession> out;
  for (const std::string& f : files) {
    const Session s = readSessionEnds(f);  // the scores are in the end line
    if (!s.complete) throw InputError(f + ": an expert session must be complete: " + s.message);
    if (!s.summary.contains("scores") || !s.summary["scores"].is_object())
      throw InputError(f + ":" + std::to_string(s.lines) + ": summary: no scores in the end line");
    ExpertSession e;
    e.file = f;
    e.scenario_id = s.header.scenario;
    try {
      e.scenario = findScenario(s.header.scenario);
    } catch (const InputError& err) {
      throw InputError(f + ":1: scenario: " + err.what());
    }
    e.scores = s.summary["scores"];
    out.push_back(std::move(e));
  }
  return out;
}

const ExpertSession* expertFor(const Scenario& scenario, const std::vector<ExpertSession>& experts,
                               std::string* why) {
  const std::string id = scenario.id.empty() ? scenario.file : scenario.id;
  for (const ExpertSession& e : experts)
    if (e.scenario_id == id) {
      if (why) *why = "same scenario";
      return &e;
    }
  for (const ExpertSession& e : experts)
    if (sameStart(e.scenario, scenario)) {
      if (why) *why = "same start as " + e.scenario_id;
      return &e;
    }
  return nullptr;
}

}  // namespace colosim
