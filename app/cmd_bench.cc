// colosim bench NAME [--json] [--hours H]
#include <iostream>

#include "bench/registry.h"
#include "app/commands.h"
#include "trainer/strict_json.h"

namespace colosim::app {

void addBenchCommand(CLI::App& app, Action& action) {
  std::string names;
  for (const BenchEntry& b : benchmarks()) names += "\n  " + b.name + ": " + b.description;
  CLI::App* cmd = app.add_subcommand("bench", "Run a benchmark and print its figures. Benchmarks:" + names);
  auto name = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto hours = std::make_shared<double>(-1.0);
  cmd->add_option("NAME", *name, "benchmark to run")->required();
  cmd->add_flag("--json", *json, "print one JSON object on stdout instead of text");
  cmd->add_option("--hours", *hours, "simulated hours, 1e-5 .. 100 (endurance only; default 1)");
  cmd->callback([&action, name, json, hours] {
    action = [name, json, hours]() -> int {
      for (const BenchEntry& b : benchmarks()) {
        if (b.name != *name) continue;
        BenchOptions options;
        if (*hours != -1.0) {
          if (!b.takes_hours) throw InputError("--hours: only the endurance benchmark takes it, not '" + *name + "'");
          if (!(*hours >= 1e-5 && *hours <= 100))
            throw InputError("--hours: " + std::to_string(*hours) + " is out of range [1e-05, 100]");
          options.hours = *hours;
        }
        const BenchOutput out = b.run(options);
        if (out.exit_code != 0) {
          std::cerr << "colosim bench " << *name << ": " << out.error << "\n";
          return out.exit_code;
        }
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
