// Organ-level hidden-effect trials (issue 17, item 4): the confusion table of the organ
// identification over seeds, on data made at the parameter file's resolution (1.5 cm, twice
// as fine as the 3 cm search) with the two-rate protocol, which the unit tests' cases do
// not use (identify/insertion/synthetic.h drawTwoRateInsertion: from 40-50 cm a slow push,
// a hold, a quick push, a hold, a withdrawal; rotation wiggle, both knobs).
//   organ_trials [--seeds N] [--first-seed S] [--duration S] [--effects none,wall_friction,...]
//                [--no-mismatch] [--search-judges-rounds] [--search-at-data-step] [--refine-every-leader]
//                [--no-guessing] [--coupling-predictor | --coupling-lag]
//                [--search-spacing M] [--data-spacing M]
//                [--threads T] [--verbose] [--report DIR]
// prints one line per case as it ends (hidden, named, magnitudes, held-out gain, RMSE over
// the sensor noise, unexplained, replays, wall time), then the confusion table (rows: hidden
// effect; columns: the first effect named, or none) and per class: named right, a wrong
// name, nothing named, the median magnitude error of right names, and for the data with
// nothing hidden the largest RMSE of the paper's model over the sensor noise. --data-spacing
// makes the recordings with another control-point spacing and scope segment length than the
// parameter file's (which the identification's refinement uses): 0.0075 m makes data finer
// than any model the identification replays, as a real colon is. --report DIR
// writes the table as a heat map (confusion.png, gnuplot), its data, the text and every case
// as JSON (identify.json). The data and every replay couple the contacts as the bench
// specimen's parameter file says (ContactParams::coupling_predictor, docs/numerics.md:
// paper.json lags); --coupling-predictor and --coupling-lag make them all use one or the other.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "identify/insertion/identify.h"
#include "identify/insertion/synthetic.h"
#include "identify/report.h"
#include "tools/confusion_plot.h"

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace colosim;
  int seeds = 10, threads = 2;
  unsigned long long first_seed = 1001;
  double duration_s = 2.0;
  bool mismatch = true;
  bool verbose = false;  // each case's candidates and diagnosis
  bool judge_fine = true;  // round 2 judged on round 1's leaders refined at the data's resolution too
  bool step_with_spacing = true;  // the search's time step scaled with its spacing
  bool choice_first = true;       // the search's choice refined first, the other leaders when needed
  bool guessing = true;           // a free thread runs the next refinement stage's likely replays
  std::optional<bool> predictor;  // the contacts' coupling predictor in the data and the replays; unset: the file's
  double search_spacing_m = 0.03;  // [m]; the data's (0.015 m): no coarse search
  double data_spacing_m = 0;       // [m]; 0: the parameter file's
  std::string report;  // folder for --report; empty: none
  std::vector<std::string> effects = {"none"};
  for (const std::string& e : organEffectNames()) effects.push_back(e);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--seeds") seeds = std::atoi(next().c_str());
    else if (a == "--first-seed") first_seed = std::strtoull(next().c_str(), nullptr, 10);
    else if (a == "--duration") duration_s = std::atof(next().c_str());
    else if (a == "--effects") effects = split(next());
    else if (a == "--no-mismatch") mismatch = false;
    else if (a == "--search-judges-rounds") judge_fine = false;
    else if (a == "--search-at-data-step") step_with_spacing = false;
    else if (a == "--refine-every-leader") choice_first = false;
    else if (a == "--no-guessing") guessing = false;
    else if (a == "--coupling-predictor") predictor = true;
    else if (a == "--coupling-lag") predictor = false;
    else if (a == "--verbose") verbose = true;
    else if (a == "--threads") threads = std::atoi(next().c_str());
    else if (a == "--search-spacing") search_spacing_m = std::atof(next().c_str());
    else if (a == "--report") report = next();
    else if (a == "--data-spacing") data_spacing_m = std::atof(next().c_str());
    else {
      std::fprintf(stderr,
                   "usage: %s [--seeds N] [--first-seed S] [--duration S] [--effects none,EFFECT,...] [--no-mismatch] "
                   "[--search-judges-rounds] [--search-at-data-step] [--refine-every-leader] [--no-guessing] [--coupling-predictor | --coupling-lag] [--search-spacing M] [--data-spacing M] [--threads T] [--verbose] [--report DIR]\n",
                   argv[0]);
      return 2;
    }
  }
  if (seeds < 1 || threads < 1 || !(duration_s >= 0.5) || !(data_spacing_m >= 0)) {
    std::fprintf(stderr, "--seeds and --threads must be >= 1, --duration >= 0.5 s, --data-spacing >= 0 m\n");
    return 2;
  }
  std::vector<int> index;
  for (const std::string& e : effects) {
    const int k = organEffectIndex(e);
    if (k < 0 && e != "none") {
      std::fprintf(stderr, "--effects: unknown effect '%s'\n", e.c_str());
      return 2;
    }
    index.push_back(k);
  }

  ReplaySetup fine = makeReplaySetup(findScenario("free_insertion_attached_rectum"));
  if (predictor) fine.params.contact.coupling_predictor = *predictor;
  ReplaySetup data = data_spacing_m > 0 ? makeReplaySetup(fine.scenario, data_spacing_m) : fine;
  if (predictor) data.params.contact.coupling_predictor = *predictor;
  InsertionIdentifyOptions opt;
  opt.threads = threads;
  opt.mismatch_term = mismatch;
  opt.judge_rounds_at_data_resolution = judge_fine;
  opt.search_step_with_spacing = step_with_spacing;
  opt.refine_choice_first = choice_first;
  opt.guess_next_replays = guessing;
  opt.search_spacing_m = search_spacing_m;
  std::printf("organ trials: %d seeds from %llu, %.3g s two-rate recordings at %.3g m, refined at %.3g m, search at %.3g m, %s\n",
              seeds, first_seed, duration_s, data.params.colon.control_point_spacing_m,
              fine.params.colon.control_point_spacing_m, opt.search_spacing_m,
              mismatch ? "mismatch term on" : "mismatch term OFF");
  std::printf("contacts' coupling: %s, in the data and the replays%s\n",
              fine.params.contact.coupling_predictor ? "the predictor" : "the lag", predictor ? "" : " (the parameter file's)");
  std::fflush(stdout);
  // confusion[hidden][named first]
  std::map<std::string, std::map<std::string, int>> confusion;
  std::map<std::string, std::vector<double>> value_error, over_noise;
  std::map<std::string, int> unexplained;
  nlohmann::json cases = nlohmann::json::array();
  const auto t0 = std::chrono::steady_clock::now();
  for (size_t c = 0; c < effects.size(); ++c) {
    for (int s = 0; s < seeds; ++s) {
      const unsigned long long seed = first_seed + s;
      const SyntheticInsertionSpec spec = drawTwoRateInsertion(seed, index[c], duration_s);
      const InsertionRecording rec = makeSyntheticInsertion(data, spec);
      const InsertionIdentifyResult r = identifyInsertion(rec, fine, opt);
      const std::string named = r.effects.empty() ? "none" : r.effects.front();
      ++confusion[effects[c]][named];
      if (r.unexplained) ++unexplained[effects[c]];
      const double found = r.effects.empty() ? 0 : organEffectValue(r.extended.params, named);  // first named
      if (!r.effects.empty() && named == effects[c]) value_error[effects[c]].push_back(std::abs(found / spec.value - 1));
      const double ratio = r.extended.rmse_N / spec.force_noise_N;
      if (index[c] < 0) over_noise[effects[c]].push_back(r.baseline.rmse_N / spec.force_noise_N);
      std::string all;
      for (const std::string& e : r.effects) all += (all.empty() ? "" : "+") + e;
      cases.push_back({{"hidden", effects[c]}, {"seed", seed}, {"hidden_value", spec.value}, {"named", r.effects},
                       {"named_value", found}, {"heldout_rmse_ratio", r.heldout_rmse_ratio},
                       {"rmse_over_noise", ratio}, {"unexplained", r.unexplained}, {"simulations", r.simulations},
                       {"seconds", r.seconds}});
      std::printf("%-21s seed %llu hidden %-9.4g named [%s] %.4g gain %.3f rmse/noise %.2f%s%s, %d replays, %.0f s\n",
                  effects[c].c_str(), seed, spec.value, all.c_str(), found,
                  r.heldout_rmse_ratio, ratio, r.unexplained ? " UNEXPLAINED" : "",
                  r.refuted_effects.empty() ? "" : " (refuted)", r.simulations, r.seconds);
      if (verbose) {
        for (const CandidateEvidence& e : r.evidence)
          std::printf("    round %d %-22s value %-9.4g held-out ratio %.3f dBIC %+.1f%s%s\n", e.round,
                      e.effect.c_str(), e.value, e.heldout_ratio, e.delta_bic, e.pays ? " pays" : "",
                      e.chosen ? " CHOSEN" : "");
        std::printf("%s", r.diagnosis.c_str());
      }
      std::fflush(stdout);
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::vector<std::string> cols = {"none"};
  for (const std::string& e : organEffectNames()) cols.push_back(e);
  std::string text;
  char line[512];
  auto add = [&](const char* fmt, auto... args) {
    std::snprintf(line, sizeof line, fmt, args...);
    text += line;
  };
  add("\nConfusion table (rows hidden, columns the first effect named), %d seeds each, %.0f s wall:\n\n| hidden |",
      seeds, wall);
  for (const std::string& k : cols) add(" %s |", k.c_str());
  add(" right | unexplained | median magnitude error |\n|---|");
  for (size_t k = 0; k <= cols.size() + 2; ++k) add("---|");
  add("\n");
  for (const std::string& e : effects) {
    add("| %s |", e.c_str());
    int total = 0;
    for (const std::string& k : cols) {
      const int n = confusion[e][k];
      total += n;
      add(" %d |", n);
    }
    add(" %d/%d | %d |", confusion[e][e], total, unexplained[e]);
    if (e == "none") {
      const auto& v = over_noise[e];
      add(" (paper's model RMSE / noise: median %.2f, largest %.2f) |\n", median(v),
          v.empty() ? NAN : *std::max_element(v.begin(), v.end()));
    } else {
      add(" %.1f %% |\n", 100 * median(value_error[e]));
    }
  }
  std::printf("%s", text.c_str());
  if (!report.empty()) {
    // The table as a heat map: the fraction of each hidden class named as each answer.
    std::vector<std::vector<int>> counts;
    for (const std::string& e : effects) {
      counts.emplace_back();
      for (const std::string& k : cols) counts.back().push_back(confusion[e][k]);
    }
    const ConfusionPlot plot =
        confusionPlot(effects, cols, counts, seeds,
                      "Organ hidden-effect trials: fraction of each hidden class named first as each answer (" +
                          std::to_string(seeds) + " seeds per class)",
                      "named first");
    const nlohmann::json result = {{"experiment", "organ_trials"}, {"seeds", seeds}, {"first_seed", first_seed},
                                   {"duration_s", duration_s}, {"search_spacing_m", opt.search_spacing_m},
                                   {"data_spacing_m", data.params.colon.control_point_spacing_m},
                                   {"refinement_spacing_m", fine.params.colon.control_point_spacing_m},
                                   {"mismatch_term", mismatch}, {"wall_s", wall}, {"cases", cases}};
    try {
      writeGnuplotReport(report, {{"confusion.dat", plot.data}}, plot.script, text, result);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "--report %s: %s\n", report.c_str(), e.what());
      return 1;
    }
  }
  return 0;
}
