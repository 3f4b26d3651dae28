// Session reports (issue 19): the timeline's events agree with the scores, the shipped
// expert sessions are the pinned runs, and `colosim score --report` pages open in a
// headless chromium with every image loaded and the numbers of `score --json`.
#include "trainer/session_report.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixture.h"
#include "session_fixture.h"
#include "trainer/expert_sessions.h"
#include "trainer/score.h"
#include "trainer/session_timeline.h"
#include "trainer/world_simulation.h"

namespace colosim {
namespace {

namespace fs = std::filesystem;

// Wall force pulses of 0.3 s (no episode) and 0.8 s (one episode), a red-out of 0.2 s,
// the lumen lost twice: the timeline marks what the Scorer counts.
TEST(SessionTimeline, MarksTheEventsTheScorerCounts) {
  ScoreOptions o;
  o.start_s = 1.0;
  Scorer scorer(o);
  TimelineRecorder rec(o);
  const double dt = 1e-3;
  for (long k = 1; k <= 6000; ++k) {
    Telemetry t;
    t.time_s = k * dt;
    const double s = t.time_s;
    t.handle_force_N = std::sin(s);
    // Before start_s the wall force is high too: the set-up is not scored nor marked.
    // Steps (k - 1) dt to k dt, in whole steps: k in (2000, 2300] is 2.0 s to 2.3 s.
    auto in = [k](long from, long to) { return k > from && k <= to; };
    t.wall_force_peak_N = k < 900 || in(2000, 2300) || in(3000, 3800) ? 9.0 : 1.0;
    t.tip_against_wall = in(4000, 4200);
    t.lumen_visible = !in(4000, 4500) && !in(5000, 5100);
    scorer.add(t);
    rec.add(t);
  }
  const nlohmann::json j = scorer.json();
  const SessionTimeline tl = rec.timeline();
  ASSERT_EQ(j["excessive_pressure_episodes"].get<int>(), 1);
  ASSERT_EQ(tl.pressure_episodes.size(), 1u);
  EXPECT_NEAR(tl.pressure_episodes[0].from_s, 3.0, 1e-9);
  EXPECT_NEAR(tl.pressure_episodes[0].to_s, 3.8, 1e-9);
  ASSERT_EQ(tl.redout.size(), 1u);
  EXPECT_NEAR(tl.redout[0].to_s - tl.redout[0].from_s, j["redout_time_s"].get<double>(), 1e-9);
  ASSERT_EQ(tl.lumen_lost_s.size(), static_cast<size_t>(j["lumen_lost_count"].get<int>()));
  ASSERT_EQ(tl.lumen_lost_s.size(), 2u);
  EXPECT_NEAR(tl.lumen_lost_s[1], 5.001, 1e-9);
  // 50 ms bins over 6 s, each keeping its largest value: the plotted peak is the scored one.
  EXPECT_EQ(tl.samples.size(), 120u);
  double peak = 0;
  for (const TimelineSample& s : tl.samples)
    if (s.time_s > o.start_s) peak = std::max(peak, std::abs(s.handle_force_N));
  EXPECT_DOUBLE_EQ(peak, j["peak_handle_force_N"].get<double>());
}

// The shipped expert sessions are the runs the golden file pins (same final state hash),
// so their recorded scores are what the simulation gives today; sigmoid_push (the same
// start) is compared with sigmoid_untwist's, free_insertion_attached_rectum (another
// anatomy and start) with none.
TEST(ExpertSessions, TheShippedOnesAreThePinnedRunsAndMatchTheirManoeuvres) {
  const std::vector<ExpertSession> experts = loadExpertSessions();
  const nlohmann::json golden =
      nlohmann::json::parse(test::readFile(std::string(COLOSIM_GOLDEN_DIR) + "/behaviour.json"));
  for (const char* name : {"sigmoid_untwist", "free_insertion"}) {
    std::string why;
    const ExpertSession* e = expertFor(findScenario(name), experts, &why);
    ASSERT_NE(e, nullptr) << name;
    EXPECT_EQ(why, "same scenario");
    // Read whole (the loader reads only the header and end line): every line is checked too.
    EXPECT_EQ(hashToHex(readSession(e->file).final_state_hash),
              golden["scenario_final_state_hash"][name].get<std::string>())
        << "the simulation changed: record " << e->file << " again (docs/file-formats.md, Expert references)";
    EXPECT_GT(e->scores["peak_handle_force_N"].get<double>(), 0.0) << name;
  }
  std::string why;
  EXPECT_EQ(expertFor(findScenario("sigmoid_push"), experts, &why), expertFor(findScenario("sigmoid_untwist"), experts));
  EXPECT_EQ(why, "same start as sigmoid_untwist");
  EXPECT_EQ(expertFor(findScenario("free_insertion_attached_rectum"), experts), nullptr);
}

using Result = test::CommandOutput;


// A 2.5 s session of the small test scenario (10 ms steps) on the colon + scope simulation.
std::string record(const test::TempDir& dir, const std::string& name) {
  const Scenario sc = loadScenario(dir.write(name + ".json", test::smallScenarioText(name)));
  const std::string path = dir.file(name + ".jsonl");
  WorldSimulation sim(sc);
  SessionWriter w(path, sessionHeaderFor(sc, "test"));
  runScenario(sc, sim, &w);
  return path;
}

std::string body(const std::string& page) {
  const size_t a = page.find("<body>"), b = page.rfind("</body>");
  return a == std::string::npos || b == std::string::npos ? "" : page.substr(a + 6, b - a - 6);
}

TEST(ScoreReport, PagesLoadInABrowserWithTheNumbersOfScoreJson) {
  const std::string chromium = COLOSIM_CHROMIUM;
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (scripts/setup installs it)";
  test::TempDir dir;
  const std::string a = record(dir, "alpha"), b = record(dir, "beta");
  const std::string report = dir.file("report");
  const Result r = test::runColosim("score " + a + " " + b + " --json --report " + report, dir);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const nlohmann::json scores = nlohmann::json::parse(r.out);  // --json: nothing else on stdout
  ASSERT_EQ(scores.size(), 2u);
  EXPECT_EQ(nlohmann::json::parse(test::readFile(report + "/score.json")), scores);

  // One page for the browser with the bodies of the cohort page and both session pages
  // (their images are relative to the folder), and a script that writes, once everything
  // has loaded, each image's natural width into the DOM that chromium dumps.
  std::string check = "<!DOCTYPE html><html><head><meta charset=\"utf-8\"></head><body>";
  int images = 0;
  for (const char* p : {"index.html", "session_01.html", "session_02.html"}) {
    const std::string page = test::readFile(report + "/" + p);
    ASSERT_NE(page.find("</html>"), std::string::npos) << p;
    EXPECT_EQ(page.find("http://"), std::string::npos) << p << ": nothing is fetched from the network";
    EXPECT_EQ(page.find("https://"), std::string::npos) << p;
    for (size_t at = page.find("<img "); at != std::string::npos; at = page.find("<img ", at + 1)) ++images;
    check += "<div data-page=\"" + std::string(p) + "\">" + body(page) + "</div>";
  }
  // The cohort's distributions, both timelines and 4 global views per session.
  EXPECT_GE(images, 2 + 2 * 4 + 10);
  check += "<script>window.addEventListener('load', () => { const p = document.createElement('pre');"
           " p.id = 'imgcheck'; p.textContent = [...document.images].map(i => i.getAttribute('src') + ' ' +"
           " i.naturalWidth).join('\\n'); document.body.appendChild(p); });</script></body></html>";
  const std::string check_page = report + "/check.html";
  std::ofstream(check_page) << check;
  const test::CommandResult dom = test::runCommand(
      "timeout 60 " + chromium + " --headless --no-sandbox --disable-gpu --user-data-dir=" + dir.file("chromium") +
      " --virtual-time-budget=3000 --dump-dom file://" + check_page + " 2>/dev/null");
  ASSERT_EQ(dom.code, 0);
  const size_t pre = dom.out.find("<pre id=\"imgcheck\">");
  ASSERT_NE(pre, std::string::npos) << "the page's script did not run:\n" << dom.out.substr(0, 2000);
  const std::string list = dom.out.substr(pre, dom.out.find("</pre>", pre) - pre);
  const std::regex img_line(R"(([\w.]+\.png) (\d+))");
  int loaded = 0;
  for (auto it = std::sregex_iterator(list.begin(), list.end(), img_line); it != std::sregex_iterator(); ++it) {
    EXPECT_GT(std::stoi((*it)[2]), 0) << (*it)[1] << " did not load";
    ++loaded;
  }
  EXPECT_EQ(loaded, images);

  // Every number cell of a session, as the browser has it, is its score in score --json:
  // data-value exactly, the text shown to 4 significant digits.
  const std::regex cell(R"re(data-session="(\d+)" data-key="(\w+)" data-value="([^"]*)">([^<]*)<)re");
  std::map<std::string, int> seen;
  for (auto it = std::sregex_iterator(dom.out.begin(), dom.out.end(), cell); it != std::sregex_iterator(); ++it) {
    const nlohmann::json& s = scores.at(std::stoi((*it)[1]) - 1);
    const std::string key = (*it)[2], value = (*it)[3], shown = (*it)[4];
    ++seen[key];
    ASSERT_TRUE(s.contains(key)) << key;
    if (s[key].is_null()) {
      EXPECT_EQ(value, "null");
      EXPECT_EQ(shown, "n/a");
      continue;
    }
    const double json_value = s[key].get<double>();
    EXPECT_EQ(std::stod(value), json_value) << key;
    EXPECT_NEAR(std::stod(shown), json_value, 5e-4 * std::abs(json_value) + 1e-300) << key << " shows " << shown;
  }
  // Each metric twice per session: the cohort table and the session's page.
  EXPECT_EQ(seen.size(), reportMetrics().size());
  for (const auto& [key, n] : seen) EXPECT_EQ(n, 4) << key;
}

TEST(ScoreReport, NeverWritesIntoAFolderWithFiles) {
  test::TempDir dir;
  const std::string a = record(dir, "alpha");
  fs::create_directories(dir.file("taken"));
  const std::string kept = dir.write("taken/index.html", "mine");
  const Result r = test::runColosim("score " + a + " --report " + dir.file("taken"), dir);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("never overwrites"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");  // stopped before any replay
  EXPECT_EQ(test::readFile(kept), "mine");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.file("taken")), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace colosim
