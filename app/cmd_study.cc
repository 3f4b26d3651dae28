// colosim study STUDY.json [--json] [--report DIR] [--threads N] [--shard K/N --out DIR] [--check]
// colosim study --merge DIR... [--json]
// Design studies: every case of the study (designs x scenarios x strategies x seeds) run
// headless, summarised per design with the paired comparison against the first design.
// The work is in trainer/study.h; docs/design-studies.md.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <tuple>
#include <thread>

#include "app/commands.h"
#include "trainer/progress.h"
#include "trainer/study.h"

namespace colosim::app {

namespace {

struct StudyOptions {
  std::string study;
  bool json = false;
  std::string report;
  unsigned threads = 0;
  std::string shard;
  std::string out;
  std::vector<std::string> merge;
  bool check = false;
};

int runStudy(const StudyOptions& o) {
  if (!o.merge.empty()) {
    if (!o.study.empty()) throw InputError("--merge takes shard folders, not a study file (" + o.study + ")");
    if (!o.shard.empty() || !o.out.empty() || !o.report.empty())
      throw InputError("--merge cannot be combined with --shard, --out or --report");
    const StudyResults r = mergeShards(o.merge);
    if (o.json) std::cout << studySummaryJson(r).dump() << "\n";
    else std::cout << studySummaryText(r);
    return 0;
  }
  if (o.study.empty()) throw InputError("colosim study: give a STUDY.json (or --merge DIR...)");
  // Every input is read and checked before any work or output.
  const Study study = loadStudy(o.study);
  std::vector<StudyCase> cases = studyCases(study);
  if (o.check) {
    std::printf("study %s: %zu cases (%zu designs x %zu scenarios x %zu strategies x %zu seeds)\n", study.name.c_str(),
                cases.size(), study.designs.size(), study.scenarios.size(), study.strategies.size(),
                study.seeds.size());
    return 0;
  }
  int k = 0, n = 0;
  if (!o.shard.empty() || !o.out.empty()) {
    if (o.shard.empty() || o.out.empty()) throw InputError("--shard K/N and --out DIR go together");
    if (!o.report.empty()) throw InputError("--report with --shard: report from a single-machine run");
    std::tie(k, n) = parseShard(o.shard);
    const std::filesystem::path file = std::filesystem::path(o.out) / ("shard-" + std::to_string(k) + "-of-" +
                                                                       std::to_string(n) + ".json");
    if (std::filesystem::exists(file)) throw InputError(file.string() + ": exists (a shard is never overwritten)");
    cases = shardCases(cases, k, n);
  }
  const int threads = o.threads > 0 ? static_cast<int>(o.threads)
                                    : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  long bar_total = 0;
  std::unique_ptr<ProgressBar> steps_bar;
  std::mutex m;
  const std::vector<CaseResult> results = runStudyCases(study, cases, threads, [&](long done, long total) {
    std::lock_guard<std::mutex> lock(m);
    if (!steps_bar) {
      bar_total = total;
      steps_bar = std::make_unique<ProgressBar>("study " + study.name + (n ? " " + o.shard : ""), bar_total,
                                                stderrIsTerminal() && !o.json);
    }
    steps_bar->update(done);
  });
  if (steps_bar) steps_bar->finish();
  if (n) {
    const std::string path = writeShard(study, k, n, cases, results, o.out);
    std::fprintf(stderr, "colosim study %s: shard %d/%d, %zu cases written to %s\n", study.name.c_str(), k, n,
                 cases.size(), path.c_str());
    return 0;
  }
  const StudyResults r = studyResults(study, results);
  if (o.json) std::cout << studySummaryJson(r).dump() << "\n";
  else std::cout << studySummaryText(r);
  if (!o.report.empty())
    for (const std::string& line : writeStudyReport(study, cases, results, o.report))
      std::fprintf(stderr, "colosim study %s: %s\n", study.name.c_str(), line.c_str());
  return 0;
}

}  // namespace

void addStudyCommand(CLI::App& app, Action& action) {
  auto o = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand("study", "Run a design study (scope designs x scenarios x strategies x seeds), "
                                              "or merge the shards of one");
  cmd->add_option("STUDY", o->study, "study file (assets/studies/*.json)");
  cmd->add_flag("--json", o->json, "print one JSON object on stdout: per design, each metric's mean and sd and the "
                                   "paired difference to the first design with its 95% interval");
  cmd->add_option("--report", o->report, "write plots (gnuplot: data, .gp scripts and PNGs) into this folder");
  cmd->add_option("--threads", o->threads, "worker threads (0: every core)")->check(CLI::Range(0u, 1024u))
      ->capture_default_str();
  cmd->add_option("--shard", o->shard, "run only shard K of N (the cases whose index mod N is K-1); needs --out");
  cmd->add_option("--out", o->out, "folder the shard's results are written to (shard-K-of-N.json)");
  cmd->add_option("--merge", o->merge, "merge the shard results in these folders (instead of running a study)")
      ->expected(1, -1);
  cmd->add_flag("--check", o->check, "read and check the study file (its scenarios and scope designs too), print its "
                                     "case count and run nothing (scripts/study-slurm does before submitting)");
  cmd->callback([&action, o] { action = [o]() -> int { return runStudy(*o); }; });
}

}  // namespace colosim::app
