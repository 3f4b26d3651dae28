// colosim: a colonoscopy simulator. A thin main: the work is in the libraries.
#include <iostream>

#include "app/commands.h"
#include "app/crash_report.h"
#include "trainer/strict_json.h"

int main(int argc, char** argv) {
  colosim::app::installCrashReport();
  CLI::App app{"colosim " COLOSIM_VERSION ": a colonoscopy simulator (Kuehl & Dumont's spline colon, extended)"};
  app.set_version_flag("--version", std::string(COLOSIM_VERSION));
  app.require_subcommand(1);
  colosim::app::Action action;
  colosim::app::addRunCommand(app, action);
  colosim::app::addBenchCommand(app, action);
  colosim::app::addScoreCommand(app, action);
  colosim::app::addReplayCommand(app, action);
  colosim::app::addIdentifyCommand(app, action);
  colosim::app::addTrainCommand(app, action);
  colosim::app::addStudyCommand(app, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    return action ? action() : 0;
  } catch (const colosim::InputError& e) {
    std::cerr << "colosim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "colosim: error: " << e.what() << "\n";
    return 1;
  }
}
