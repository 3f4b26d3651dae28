// The benchmarks behind `colosim bench NAME [--json]`: the one place where colosim's
// speed figures are measured. Each benchmark runs in one process and reports medians
// and ratios measured in that run (this machine is shared and noisy: no absolute
// thresholds are asserted here; the README quotes the figures).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace colosim {

struct BenchOutput {
  nlohmann::json json;  ///< printed with --json (one object)
  std::string text;     ///< printed otherwise, for people
};

struct BenchEntry {
  std::string name;
  std::string description;
  std::function<BenchOutput()> run;
};

/// All benchmarks, in a fixed order.
const std::vector<BenchEntry>& benchmarks();

// One function per benchmark, each in its own file.
BenchOutput benchColon();
BenchOutput benchContacts();
BenchOutput benchUntwist();
BenchOutput benchIdentify();
BenchOutput benchRender();

}  // namespace colosim
