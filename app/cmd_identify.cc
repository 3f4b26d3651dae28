// colosim identify DATA.csv [--json] [--report DIR] [--law-out FILE]: fits the paper's
// Voigt law to a measured tension test, names the effects it misses, extends the law and
// measures the gain (identify/tension/identify.h; docs/identification.md).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "app/commands.h"
#include "identify/insertion/identify.h"
#include "identify/insertion/report.h"
#include "identify/tension/identify.h"
#include "identify/tension/report.h"
#include "trainer/progress.h"
#include "trainer/tension_law_file.h"

namespace colosim::app {

namespace {

struct IdentifyOptionsCli {
  std::string data;
  bool json = false;
  std::string report;
  std::string law_out;
};

// A recorded insertion (# experiment: insertion): identification at the organ level
// (identify/insertion/identify.h; docs/organ-identification.md).
int runIdentifyInsertion(const IdentifyOptionsCli& o) {
  const InsertionRecording rec = readInsertionRecording(o.data);
  const Scenario scenario = recordingScenario(rec);
  const ReplaySetup setup = makeReplaySetup(scenario);
  InsertionIdentifyOptions opt;
  ProgressBar bar("identify " + rec.scenario, 1000, stderrIsTerminal() && !o.json);
  opt.on_progress = [&](long done, long planned) { bar.update(done * 1000 / std::max(planned, 1L)); };
  const InsertionIdentifyResult r = identifyInsertion(rec, setup, opt);
  bar.finish();
  const nlohmann::json j = organIdentifyJson(rec, r);
  if (!o.law_out.empty())
    writeOrganParameters(o.law_out, scenario.params_path, r.extended, "colosim identify " + o.data);
  if (!o.report.empty()) writeOrganReport(o.report, rec, r);
  if (o.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "colosim identify " << o.data << ": insertion, " << rec.rows() << " rows, scenario "
              << rec.scenario << "\n" << r.diagnosis;
    if (!o.law_out.empty())
      std::cout << "Parameters written to " << o.law_out << " (wall friction, colon bending, lifter stiffening"
                << (organLawParams(setup.params, r.extended.params) ? " and the tension law as colon.tension_law" : "")
                << "): colosim run " << rec.scenario << " --params " << o.law_out << "\n";
    if (!o.report.empty()) std::cout << "Report written to " << o.report << "/\n";
  }
  return 0;
}

int runIdentify(const IdentifyOptionsCli& o) {
  // Everything is read and computed before anything is written: a bad file changes nothing.
  if (measurementExperiment(o.data) == "insertion") return runIdentifyInsertion(o);
  const TensionTest test = readTensionTest(o.data);
  IdentifyOptions opt;
  ProgressBar bar("identify tension", 1000, stderrIsTerminal() && !o.json);
  opt.on_progress = [&](long done, long planned) { bar.update(done * 1000 / std::max(planned, 1L)); };
  const IdentifyResult r = identifyTension(test, opt);
  bar.finish();
  if (!o.law_out.empty()) {
    std::vector<double> sd;
    for (const ParamEstimate& p : r.extended.params)
      if (p.name != "offset_N") sd.push_back(p.sd);
    writeTensionLawFile(o.law_out, r.extended.law, sd, "colosim identify " + o.data);
  }
  if (!o.report.empty()) writeIdentifyReport(o.report, test, r);
  if (o.json) {
    std::cout << identifyJson(test, r).dump() << "\n";
  } else {
    std::cout << "colosim identify " << o.data << ": " << test.rows() << " rows, " << r.cycles << " loading cycles\n"
              << r.diagnosis;
    if (!o.law_out.empty()) std::cout << "Law written to " << o.law_out << " (colosim run --tension-law)\n";
    if (!o.report.empty()) std::cout << "Report written to " << o.report << "/\n";
  }
  return 0;
}

}  // namespace

void addIdentifyCommand(CLI::App& app, Action& action) {
  auto o = std::make_shared<IdentifyOptionsCli>();
  CLI::App* cmd = app.add_subcommand(
      "identify", "Identify the colon's tension law from a measured tension test, or the organ-level model from a "
      "recorded insertion (CSV, docs/identification.md, docs/organ-identification.md)");
  cmd->add_option("DATA", o->data, "measurement file (# colosim-measurement v1, experiment: tension or insertion)")->required();
  cmd->add_flag("--json", o->json, "print one JSON object on stdout instead of text");
  cmd->add_option("--report", o->report, "write PNG plots (gnuplot) and the diagnosis into this folder");
  cmd->add_option("--law-out", o->law_out, "write the identified law (JSON) for colosim run --tension-law; for an insertion, the "
                  "identified parameter file (friction, bending, lifter stiffening, tension law) for colosim run "
                  "SCENARIO --params");
  cmd->callback([&action, o] { action = [o]() -> int { return runIdentify(*o); }; });
}

}  // namespace colosim::app
