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
  int exit_code = 0;    ///< the command's exit status (2: the benchmark cannot run in this build)
  std::string error;    ///< printed on stderr when exit_code is not 0
};

/// Options of `colosim bench` that some benchmarks take.
struct BenchOptions {
  double hours = 1.0;  ///< simulated hours (endurance) [h]
};

struct BenchEntry {
  std::string name;
  std::string description;
  std::function<BenchOutput(const BenchOptions&)> run;
  bool takes_hours = false;  ///< reads BenchOptions::hours (--hours)
};

/// All benchmarks, in a fixed order.
const std::vector<BenchEntry>& benchmarks();

// One function per benchmark, each in its own file.
BenchOutput benchColon();
BenchOutput benchContacts();
BenchOutput benchUntwist();
BenchOutput benchIdentify();
BenchOutput benchRender();
BenchOutput benchEndurance(const BenchOptions& options);
BenchOutput benchPeerDefault();  // bench_peer.h

}  // namespace colosim
