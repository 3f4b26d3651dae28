#include "trainer/session_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/input_error.h"
#include "trainer/frame_export.h"
#include "trainer/score.h"
#include "trainer/report_files.h"

namespace colosim {

namespace fs = std::filesystem;

namespace {

// One GL context renders at a time across the worker threads (glad's function pointers
// are shared by the process).
std::mutex& renderMutex() {
  static std::mutex m;
  return m;
}

// Labels of the compared metrics (units from Scorer::units()).
struct Metric {
  const char* key;
  const char* label;
};
const std::vector<Metric>& metrics() {
  static const std::vector<Metric> m = {
      {"time_to_caecum_s", "time to caecum"},
      {"peak_handle_force_N", "peak handle force"},
      {"peak_handle_torque_Nm", "peak handle torque"},
      {"high_force_time_pct", "time above 10 N at the handle"},
      {"peak_wall_force_N", "peak wall force"},
      {"excessive_pressure_episodes", "excessive-pressure episodes"},
      {"discomfort_index", "discomfort index"},
      {"loop_time_s", "time with a loop"},
      {"max_loop_turns", "largest loop"},
      {"redout_time_s", "red-out time"},
      {"lumen_lost_count", "lumen lost"},
      {"mucosa_visualised_pct", "mucosa visualised"},
      {"tip_path_m", "tip path"},
      {"duration_s", "scored duration"},
  };
  return m;
}

std::string unitOf(const std::string& key) {
  const auto& u = Scorer::units();
  const auto it = u.find(key);
  if (it == u.end()) return "";
  // The long explanations of some units stay in docs/file-formats.md: the unit alone here.
  const std::string& s = it->second;
  const size_t cut = s.find(" (");
  return cut == std::string::npos ? s : s.substr(0, cut);
}

std::string html(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// A number cell: shown to 4 significant digits, the exact value (round-trip) in data-value.
std::string numberCell(const nlohmann::json& v, const std::string& attrs) {
  if (!v.is_number()) return "<td " + attrs + " data-value=\"null\">n/a</td>";
  const double x = v.get<double>();
  return "<td " + attrs + " data-value=\"" + fmt("%.17g", x) + "\">" + fmt("%.4g", x) + "</td>";
}

std::string sessionStem(size_t i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "session_%02zu", i + 1);
  return buf;
}

const char* kStyle =
    "<style>body{font-family:sans-serif;margin:1.5em;max-width:1100px}table{border-collapse:collapse;margin:0.8em 0}"
    "td,th{border:1px solid #bbb;padding:2px 8px;text-align:right}th{background:#eee}td.l,th.l{text-align:left}"
    "figure{display:inline-block;margin:0.4em;width:430px;vertical-align:top}div.wide{overflow-x:auto}figcaption{font-size:90%;color:#444}"
    ".k{display:inline-block;width:1em;height:0.8em;margin:0 0.3em}</style>";

std::string page(const std::string& title, const std::string& body) {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + html(title) + "</title>" +
         kStyle + "</head>\n<body>\n<h1>" + html(title) + "</h1>\n" + body + "</body></html>\n";
}

// The gnuplot commands of one session's timeline (7 panels over time, the events marked
// on every panel).
std::string timelineScript(const std::string& stem, const SessionReportEntry& e) {
  const SessionTimeline& tl = e.timeline;
  const nlohmann::json& th = e.scores["thresholds"];
  std::ostringstream g;
  const double end_s = tl.samples.back().time_s;
  g << "reset\nset terminal pngcairo noenhanced size 900,1300 font ',10'\nset output '" << stem << "_timeline.png'\n"
    << "set multiplot layout 7,1 margins 0.1,0.98,0.05,0.97 spacing 0,0.012\nset format y '%.5g'\n"
    << "set xrange [0:" << fmt("%.6g", std::max(end_s, 1e-3)) << "]\nset grid\nset key off\n"
    << "set format x ''\n";
  int n = 1;
  if (tl.start_s > 0)
    g << "set object " << n++ << " rect from 0, graph 0 to " << tl.start_s
      << ", graph 1 fc rgb '#e4e4e4' fs solid 1 noborder behind\n";
  for (const TimeInterval& p : tl.pressure_episodes)
    g << "set object " << n++ << " rect from " << fmt("%.6g", p.from_s) << ", graph 0 to " << fmt("%.6g", p.to_s)
      << ", graph 1 fc rgb '#ffb0b0' fs solid 0.6 noborder behind\n";
  for (const TimeInterval& r : tl.redout)
    g << "set object " << n++ << " rect from " << fmt("%.6g", r.from_s) << ", graph 0 to "
      << fmt("%.6g", std::max(r.to_s, r.from_s + 1e-3)) << ", graph 0.06 fc rgb '#c00000' fs solid 1 noborder front\n";
  for (size_t k = 0; k < tl.lumen_lost_s.size(); ++k)
    g << "set arrow " << k + 1 << " from " << fmt("%.6g", tl.lumen_lost_s[k]) << ", graph 0 to "
      << fmt("%.6g", tl.lumen_lost_s[k]) << ", graph 1 nohead lc rgb '#1060d0' dt 2 front\n";
  const std::string dat = "'" + stem + "_timeline.dat'";
  auto panel = [&](int col, const std::string& ylabel, const std::string& extra) {
    g << "set ylabel '" << ylabel << "'\nplot " << dat << " using 1:" << col << " with lines lw 1.5 lc rgb '#202020'"
      << extra << "\n";
  };
  panel(2, "handle force [N]", "");
  panel(3, "handle torque [N m]", "");
  panel(4, "wall force [N]",
        ", " + fmt("%.6g", th.value("excessive_wall_force_N", 5.0)) + " with lines dt 2 lc rgb '#c00000'");
  panel(5, "loop [turns]", "");
  panel(8, "colon stretch [-]",
        ", " + fmt("%.6g", th.value("discomfort_strain", 0.03)) + " with lines dt 2 lc rgb '#c07000'");
  panel(6, "mesentery stretch [-]",
        ", " + fmt("%.6g", th.value("discomfort_stretch", 5.0)) + " with lines dt 2 lc rgb '#a0a0a0'");
  g << "set format x '%g'\nset xlabel 'time [s]'\n";
  panel(7, "tip depth [m]", "");
  g << "unset multiplot\n";
  return g.str();
}

std::string timelineData(const SessionTimeline& tl) {
  std::ostringstream d;
  d << "# time_s handle_force_N handle_torque_Nm wall_force_N loop_turns mesentery_stretch tip_arclength_m "
       "colon_stretch\n";
  for (const TimelineSample& s : tl.samples)
    d << fmt("%.6g", s.time_s) << ' ' << fmt("%.6g", s.handle_force_N) << ' ' << fmt("%.6g", s.handle_torque_Nm)
      << ' ' << fmt("%.6g", s.wall_force_N) << ' ' << fmt("%.6g", s.loop_turns) << ' '
      << fmt("%.6g", s.mesentery_stretch) << ' ' << fmt("%.6g", s.tip_arclength_m) << ' '
      << fmt("%.6g", s.colon_stretch) << '\n';
  return d.str();
}

std::string expertLabel(const ExpertSession& e) { return "expert (" + e.scenario_id + ")"; }

// A string inside single quotes in a gnuplot script.
std::string gnuplotText(const std::string& s) {
  std::string o;
  for (char c : s) o += c == '\'' ? std::string("''") : std::string(1, c);
  return o;
}

std::string sessionPage(size_t i, const SessionReportEntry& e) {
  const nlohmann::json& j = e.scores;
  const std::string stem = sessionStem(i);
  std::ostringstream b;
  b << "<p><a href=\"index.html\">cohort</a> &middot; session " << i + 1 << "</p>\n<table>\n"
    << "<tr><th class=\"l\">session file</th><td class=\"l\">" << html(j.value("session", "")) << "</td></tr>\n"
    << "<tr><th class=\"l\">scenario</th><td class=\"l\">" << html(j.value("scenario", "")) << "</td></tr>\n"
    << "<tr><th class=\"l\">steps replayed</th><td class=\"l\">" << j.value("steps", 0L)
    << (j.value("truncated", false) ? " (truncated recording)" : "") << "</td></tr>\n"
    << "<tr><th class=\"l\">replay reproduces the recording</th><td class=\"l\">"
    << (j.value("state_hash_reproduced", false) ? "yes" : "NO") << "</td></tr>\n"
    << "<tr><th class=\"l\">expert reference</th><td class=\"l\">"
    << (e.expert ? html(e.expert->file) + " (" + html(e.expert_why) + ")" : std::string("none shipped for this scenario"))
    << "</td></tr>\n</table>\n";

  b << "<h2>Scores</h2>\n<table>\n<tr><th class=\"l\">metric</th><th>value</th><th class=\"l\">unit</th><th>"
    << (e.expert ? html(expertLabel(*e.expert)) : std::string("expert")) << "</th></tr>\n";
  for (const Metric& m : metrics()) {
    b << "<tr><td class=\"l\">" << html(m.label) << " <code>" << m.key << "</code></td>"
      << numberCell(j.contains(m.key) ? j[m.key] : nlohmann::json(), "data-session=\"" + std::to_string(i + 1) +
                                                                         "\" data-key=\"" + m.key + "\"")
      << "<td class=\"l\">" << html(unitOf(m.key)) << "</td>"
      << numberCell(e.expert && e.expert->scores.contains(m.key) ? e.expert->scores[m.key] : nlohmann::json(),
                    std::string("data-expert=\"1\" data-key=\"") + m.key + "\"")
      << "</tr>\n";
  }
  b << "</table>\n";

  const SessionTimeline& tl = e.timeline;
  b << "<h2>Timeline</h2>\n";
  if (tl.samples.empty()) {
    b << "<p>No steps to plot.</p>\n";
  } else {
    b << "<p>Marked on every panel: <span class=\"k\" style=\"background:#ffb0b0\"></span>excessive-pressure "
         "episodes (" << tl.pressure_episodes.size()
      << "), <span class=\"k\" style=\"background:#c00000\"></span>red-out (" << tl.redout.size()
      << " times, the band at the bottom), <span class=\"k\" style=\"border-left:2px dashed #1060d0\"></span>lumen "
         "lost (" << tl.lumen_lost_s.size() << " times)";
    if (tl.start_s > 0)
      b << ", <span class=\"k\" style=\"background:#e4e4e4\"></span>the scenario's set-up (not scored, before "
        << fmt("%g", tl.start_s) << " s)";
    b << ". Dashed lines: the excessive wall force, discomfort (colon stretch) and mesentery thresholds. Each point is the largest value "
         "over 50 ms.</p>\n<img src=\"" << stem << "_timeline.png\" alt=\"timelines of " << html(j.value("session", ""))
      << "\" width=\"900\">\n";
    auto list = [&](const char* name, const std::vector<TimeInterval>& v) {
      if (v.empty()) return;
      b << "<p>" << name << " [s]: ";
      for (size_t k = 0; k < v.size(); ++k)
        b << (k ? ", " : "") << fmt("%.2f", v[k].from_s) << "&ndash;" << fmt("%.2f", v[k].to_s);
      b << "</p>\n";
    };
    list("Excessive-pressure episodes", tl.pressure_episodes);
    list("Red-out", tl.redout);
    if (!tl.lumen_lost_s.empty()) {
      b << "<p>Lumen lost at [s]: ";
      for (size_t k = 0; k < tl.lumen_lost_s.size(); ++k) b << (k ? ", " : "") << fmt("%.2f", tl.lumen_lost_s[k]);
      b << "</p>\n";
    }
  }
  b << "<h2>The scope in the global view</h2>\n";
  if (e.views.empty()) b << "<p>This simulation has nothing to draw.</p>\n";
  for (size_t k = 0; k < e.views.size(); ++k)
    b << "<figure><img src=\"" << stem << "_view_" << k + 1 << ".png\" width=\"" << e.views[k].image.width
      << "\" height=\"" << e.views[k].image.height << "\" alt=\"global view at " << fmt("%.2f", e.views[k].time_s)
      << " s\"><figcaption>t = " << fmt("%.2f", e.views[k].time_s) << " s</figcaption></figure>\n";
  return page("Session " + std::to_string(i + 1) + ": " + j.value("session", ""), b.str());
}

std::string cohortPage(const std::vector<SessionReportEntry>& entries, const std::vector<ExpertSession>& experts,
                       const std::vector<std::string>& plotted) {
  std::ostringstream b;
  b << "<p>" << entries.size() << " session" << (entries.size() == 1 ? "" : "s")
    << ", replayed and scored by colosim score; the expert references are the shipped expert sessions' scores"
    << " (assets/sessions/expert/). Definitions and thresholds: docs/file-formats.md (Scores).</p>\n";
  b << "<h2>Sessions</h2>\n<div class=\"wide\"><table>\n<tr><th>#</th><th class=\"l\">session</th><th class=\"l\">scenario</th>"
       "<th class=\"l\">expert reference</th>";
  for (const Metric& m : metrics()) b << "<th>" << html(m.label) << " [" << html(unitOf(m.key)) << "]</th>";
  b << "</tr>\n";
  for (size_t i = 0; i < entries.size(); ++i) {
    const nlohmann::json& j = entries[i].scores;
    b << "<tr><td>" << i + 1 << "</td><td class=\"l\"><a href=\"" << sessionStem(i) << ".html\">"
      << html(j.value("session", "")) << "</a></td><td class=\"l\">" << html(j.value("scenario", ""))
      << "</td><td class=\"l\">" << (entries[i].expert ? html(entries[i].expert->scenario_id) : std::string("none"))
      << "</td>";
    for (const Metric& m : metrics())
      b << numberCell(j.contains(m.key) ? j[m.key] : nlohmann::json(),
                      "data-session=\"" + std::to_string(i + 1) + "\" data-key=\"" + m.key + "\"");
    b << "</tr>\n";
  }
  for (const ExpertSession& x : experts) {
    b << "<tr><td></td><td class=\"l\" title=\"" << html(x.file) << "\">expert session "
      << html(fs::path(x.file).filename().string()) << "</td><td class=\"l\">" << html(x.scenario_id)
      << "</td><td class=\"l\">expert</td>";
    for (const Metric& m : metrics())
      b << numberCell(x.scores.contains(m.key) ? x.scores[m.key] : nlohmann::json(),
                      "data-expert-scenario=\"" + html(x.scenario_id) + "\" data-key=\"" + m.key + "\"");
    b << "</tr>\n";
  }
  b << "</table></div>\n<h2>Distributions</h2>\n<p>Each session's value (by its number) against the expert references "
       "(dashed lines); min, median and max of the cohort below each plot.</p>\n";
  for (const Metric& m : metrics()) {
    std::vector<double> v;
    for (const SessionReportEntry& e : entries)
      if (e.scores.contains(m.key) && e.scores[m.key].is_number()) v.push_back(e.scores[m.key].get<double>());
    b << "<figure>";
    if (std::find(plotted.begin(), plotted.end(), m.key) != plotted.end())
      b << "<img src=\"cohort_" << m.key << ".png\" width=\"420\" height=\"260\" alt=\"" << html(m.label) << "\">";
    std::sort(v.begin(), v.end());
    b << "<figcaption>" << html(m.label) << " [" << html(unitOf(m.key)) << "]: ";
    if (v.empty()) {
      b << "not measured in these sessions";
    } else {
      const double median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
      b << "min " << fmt("%.4g", v.front()) << ", median " << fmt("%.4g", median) << ", max " << fmt("%.4g", v.back());
    }
    b << "</figcaption></figure>\n";
  }
  return page("colosim cohort report", b.str());
}

}  // namespace

const std::vector<std::string>& reportMetrics() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k;
    for (const Metric& m : metrics()) k.push_back(m.key);
    return k;
  }();
  return keys;
}

// One session's recorders, on the worker thread that replays it.
struct ReportCollector::Session {
  std::unique_ptr<TimelineRecorder> timeline;
  std::unique_ptr<SceneImager> imager;
  std::vector<long> moments;  // steps at which to draw the global view
  size_t next_moment = 0;
};

ReportCollector::ReportCollector(size_t sessions, const std::vector<ExpertSession>& experts,
                                 const ReportOptions& options)
    : entries_(sessions), sessions_(sessions), experts_(experts), o_(options) {}

ReportCollector::~ReportCollector() {
  std::lock_guard<std::mutex> lock(renderMutex());
  sessions_.clear();  // GL contexts go one at a time too
}

SessionHooksFactory ReportCollector::hooks() {
  return [this](size_t index, const ReplayPlan& plan, RunHooks& hooks) {
    SessionReportEntry& entry = entries_[index];
    entry.expert = expertFor(plan.scenario, experts_, &entry.expert_why);
    auto s = std::make_shared<Session>();
    sessions_[index] = s;
    s->timeline = std::make_unique<TimelineRecorder>(plan.scenario.scoring);
    s->imager = std::make_unique<SceneImager>("global", o_.view_width_px, o_.view_height_px);
    const long steps = plan.session.steps;
    for (int k = 0; k < o_.moments; ++k) {
      const long step = o_.moments > 1 ? std::lround(static_cast<double>(steps) * k / (o_.moments - 1)) : 0;
      if (s->moments.empty() || step > s->moments.back()) s->moments.push_back(step);
    }
    hooks.on_step = [s](const Telemetry& t) { s->timeline->add(t); };
    hooks.frame_every_steps = 1;
    hooks.on_frame = [this, s, index](const Simulation& sim, long steps_done) {
      if (s->next_moment >= s->moments.size() || steps_done != s->moments[s->next_moment]) return;
      ++s->next_moment;
      std::lock_guard<std::mutex> lock(renderMutex());
      SessionReportEntry::View v;
      v.time_s = sim.time_s();
      if (s->imager->render(sim, v.image)) entries_[index].views.push_back(std::move(v));
      if (s->next_moment == s->moments.size()) s->imager.reset();  // its GL context ends on this thread
    };
  };
}

std::vector<SessionReportEntry> ReportCollector::takeEntries() {
  for (size_t i = 0; i < entries_.size(); ++i)
    if (sessions_[i]) entries_[i].timeline = sessions_[i]->timeline->timeline();
  return std::move(entries_);
}

void checkReportDir(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && (!fs::is_directory(dir, ec) || !fs::is_empty(dir, ec)))
    throw InputError(dir + ": exists and is not an empty folder (--report never overwrites files)");
}

void writeSessionReport(const std::string& dir, const std::vector<SessionReportEntry>& entries,
                        const std::vector<ExpertSession>& experts) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw std::runtime_error(dir + ": cannot create the report folder");
  const fs::path d(dir);
  std::ostringstream script;
  nlohmann::json all = nlohmann::json::array();
  for (size_t i = 0; i < entries.size(); ++i) {
    const SessionReportEntry& e = entries[i];
    all.push_back(e.scores);
    const std::string stem = sessionStem(i);
    if (!e.timeline.samples.empty()) {
      writeReportText(d / (stem + "_timeline.dat"), timelineData(e.timeline));
      script << timelineScript(stem, e);
    }
    for (size_t k = 0; k < e.views.size(); ++k)
      writePng((d / (stem + "_view_" + std::to_string(k + 1) + ".png")).string(), e.views[k].image);
    writeReportText(d / (stem + ".html"), sessionPage(i, e));
  }
  // The cohort: one strip plot per metric, the expert references as dashed lines.
  std::vector<std::string> plotted;
  for (const Metric& m : metrics()) {
    std::ostringstream dat;
    int points = 0;
    for (size_t i = 0; i < entries.size(); ++i) {
      const nlohmann::json& j = entries[i].scores;
      if (j.contains(m.key) && j[m.key].is_number()) {
        dat << i + 1 << ' ' << fmt("%.17g", j[m.key].get<double>()) << '\n';
        ++points;
      }
    }
    if (points == 0) continue;
    plotted.push_back(m.key);
    const std::string name = std::string("cohort_") + m.key;
    writeReportText(d / (name + ".dat"), dat.str());
    script << "reset\nset terminal pngcairo noenhanced size 420,260 font ',9'\nset output '" << name << ".png'\n"
           << "set xrange [0.5:" << entries.size() + 0.5 << "]\nset xtics 1\nset xlabel 'session'\n"
           << "set ylabel '" << m.label << " [" << unitOf(m.key) << "]'\nset grid ytics\n"
           << "set offsets 0, 0, graph 0.15, graph 0.15\nset key outside top center horizontal font ',8'\n"
           << "plot '" << name << ".dat' using 1:2 with points pt 7 ps 1.3 lc rgb '#1060d0' title 'sessions'";
    int colour = 0;
    static const char* kColours[] = {"#008800", "#c07000", "#800080", "#006080"};
    for (const ExpertSession& x : experts)
      if (x.scores.contains(m.key) && x.scores[m.key].is_number())
        script << ", " << fmt("%.17g", x.scores[m.key].get<double>()) << " with lines dt 2 lw 1.5 lc rgb '"
               << kColours[colour++ % 4] << "' title '" << gnuplotText(expertLabel(x)) << "'";
    script << "\n";
  }
  writeReportText(d / "index.html", cohortPage(entries, experts, plotted));
  writeReportText(d / "score.json", all.dump(2) + "\n");
  writeReportText(d / "report.gp", script.str());
  runReportGnuplot(d);
}

}  // namespace colosim
