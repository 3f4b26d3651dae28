// Subcommands of `colosim`. Each adds itself to the app and, when chosen, stores the
// action to run after parsing. Actions return the process exit code:
// 0 success, 1 failure, 2 bad input (InputError: a file or value that cannot be used).
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace colosim::app {

using Action = std::function<int()>;

void addRunCommand(CLI::App& app, Action& action);
void addBenchCommand(CLI::App& app, Action& action);
void addScoreCommand(CLI::App& app, Action& action);
void addReplayCommand(CLI::App& app, Action& action);
void addIdentifyCommand(CLI::App& app, Action& action);
void addTrainCommand(CLI::App& app, Action& action);
void addStudyCommand(CLI::App& app, Action& action);

}  // namespace colosim::app
