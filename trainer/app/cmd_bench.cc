// colosim bench NAME [--json]
#include <iostream>

#include "bench/registry.h"
#include "trainer/app/commands.h"
#include "trainer/strict_json.h"

namespace colosim::app {

void addBenchCommand(CLI::App& app, Action& action) {
  std::string names;
  for (const BenchEntry& b : benchmarks()) names += "\n  " + b.name + ": " + b.description;
  CLI::App* cmd = app.add_subcommand("bench", "Run a benchmark and print its figures. Benchmarks:" + names);
  auto name = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("NAME", *name, "benchmark to run")->required();
  cmd->add_flag("--json", *json, "print one JSON object on stdout instead of text");
  cmd->callback([&action, name, json] {
    action = [name, json]() -> int {
      for (const BenchEntry& b : benchmarks()) {
        if (b.name != *name) continue;
        const BenchOutput out = b.run();
        if (*json) std::cout << out.json.dump() << "\n";
        else std::cout << out.text;
        return 0;
      }
      std::string list;
      for (const BenchEntry& b : benchmarks()) list += " " + b.name;
      throw InputError("unknown benchmark '" + *name + "' (known:" + list + ")");
    };
  });
}

}  // namespace colosim::app
