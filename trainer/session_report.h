// `colosim score SESSION... --report DIR`: HTML pages that show what happened when in
// each session (timelines with the events marked, the scope in the global view at a few
// moments) and how a cohort compares with the expert references. Plots by gnuplot
// (Debian's gnuplot-nox, pngcairo), views by the offscreen renderer; plain HTML with
// nothing fetched from the network. Format: docs/file-formats.md ("Session reports").
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/image.h"
#include "trainer/expert_sessions.h"
#include "trainer/replay.h"
#include "trainer/session_timeline.h"

namespace colosim {

/// What a report shows of one session.
struct SessionReportEntry {
  nlohmann::json scores;  ///< the session's object of `colosim score --json`
  SessionTimeline timeline;
  struct View {
    double time_s = 0;  ///< [s]
    Image image;
  };
  std::vector<View> views;  ///< the global view at a few moments, first to last step
  const ExpertSession* expert = nullptr;  ///< expertFor(the session's scenario)
  std::string expert_why;
};

struct ReportOptions {
  int view_width_px = 320, view_height_px = 240;  ///< each global view [px]
  int moments = 4;  ///< global views per session, evenly spread from the first to the last step
};

/// Collects timelines and global views while replaySessions replays the sessions (its
/// add_hooks), on its worker threads; each renders in its own offscreen context, one at
/// a time.
class ReportCollector {
 public:
  ReportCollector(size_t sessions, const std::vector<ExpertSession>& experts, const ReportOptions& options = {});
  ~ReportCollector();
  SessionHooksFactory hooks();
  /// After the replay: one entry per session in the order given, with its timeline,
  /// views and expert reference (fill in `scores`).
  std::vector<SessionReportEntry> takeEntries();

 private:
  struct Session;
  std::vector<SessionReportEntry> entries_;
  std::vector<std::shared_ptr<Session>> sessions_;
  const std::vector<ExpertSession>& experts_;
  ReportOptions o_;
};

/// InputError unless `dir` is new or empty (a report never overwrites files).
void checkReportDir(const std::string& dir);

/// Writes the report into `dir` (created): index.html (the cohort: every session's
/// scores, the per-metric distributions against the expert references), session_NN.html
/// per session (NN from 01 in the order given), their PNG plots and views, the data and
/// script gnuplot drew them from (report.gp, gnuplot.log) and score.json (what
/// `colosim score --json` prints). std::runtime_error when a file cannot be written or
/// gnuplot fails.
void writeSessionReport(const std::string& dir, const std::vector<SessionReportEntry>& entries,
                        const std::vector<ExpertSession>& experts);

/// The metrics the cohort page compares, in its order: score keys of Scorer::json().
const std::vector<std::string>& reportMetrics();

}  // namespace colosim
