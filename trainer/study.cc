#include "trainer/study.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <atomic>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "trainer/assets.h"
#include "trainer/json_position.h"
#include "trainer/lumen_following.h"
#include "trainer/replay.h"
#include "trainer/session.h"
#include "trainer/strict_json.h"
#include "trainer/world_simulation.h"

namespace colosim {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Reading a study file.

namespace {

Study studyFromJson(const nlohmann::json& j, const std::string& path) {
  JsonObject top(j, path);
  top.formatAndVersion("colosim-study");
  Study s;
  s.file = path;
  s.name = top.string("name");
  if (s.name.empty() || s.name.size() > 200) top.fail("name", "expected 1 to 200 characters");
  s.description = top.string("description");

  const nlohmann::json& designs = top.list("designs", 1, 1000);
  std::set<std::string> names;
  for (size_t i = 0; i < designs.size(); ++i) {
    JsonObject d(designs[i], path, "designs[" + std::to_string(i) + "]");
    StudyDesign sd;
    sd.name = d.string("name");
    if (sd.name.empty() || sd.name.size() > 100) d.fail("name", "expected 1 to 100 characters");
    if (!names.insert(sd.name).second) d.fail("name", "'" + sd.name + "' names two designs");
    if (d.has("scope")) {
      sd.scope = d.string("scope");
      if (sd.scope.empty()) d.fail("scope", "must not be empty");
      sd.scope_path = sd.scope[0] == '/' ? sd.scope : assetPath(sd.scope);
      std::error_code ec;
      if (!fs::is_regular_file(sd.scope_path, ec))
        d.fail("scope", "no such file: " + sd.scope_path + " (paths are relative to " + assetDir() + ")");
    }
    if (d.has("shaft_bending_stiffness_Nm2"))
      sd.shaft_bending_stiffness_Nm2 = d.number("shaft_bending_stiffness_Nm2", 1e-4, 10.0);
    if (d.has("stiffness_level")) sd.stiffness_level = d.integer("stiffness_level", 0, 100);
    if (d.has("stiffen_from_s")) {
      if (!sd.stiffness_level) d.fail("stiffen_from_s", "needs a stiffness_level");
      sd.stiffen_from_s = d.number("stiffen_from_s", 0.0, 1e5);
    }
    d.ignore("note");
    d.finish();
    s.designs.push_back(sd);
  }

  const nlohmann::json& scenarios = top.list("scenarios", 1, 1000);
  for (size_t i = 0; i < scenarios.size(); ++i) {
    const std::string key = "scenarios[" + std::to_string(i) + "]";
    if (!scenarios[i].is_string() || scenarios[i].get<std::string>().empty())
      top.fail(key, "expected a scenario name or path");
    const std::string name = scenarios[i].get<std::string>();
    try {
      resolveScenarioPath(name);
    } catch (const InputError& e) {
      top.fail(key, e.what());
    }
    if (std::find(s.scenarios.begin(), s.scenarios.end(), name) != s.scenarios.end())
      top.fail(key, "'" + name + "' is listed twice");
    s.scenarios.push_back(name);
  }

  const nlohmann::json& strategies = top.list("strategies", 1, 100);
  for (size_t i = 0; i < strategies.size(); ++i) {
    const std::string key = "strategies[" + std::to_string(i) + "]";
    StudyStrategy st;
    if (strategies[i].is_string()) {
      st.kind = strategies[i].get<std::string>();
      if (st.kind != "scripted")
        top.fail(key, "expected \"scripted\" or {\"kind\": \"lumen_following\", \"end_s\": ...}, got '" + st.kind + "'");
    } else {
      JsonObject o(strategies[i], path, key);
      st.kind = o.choice("kind", {"scripted", "lumen_following"});
      if (st.kind == "lumen_following") st.end_s = o.number("end_s", 0.5, 1e5);
      o.ignore("note");
      o.finish();
    }
    for (const StudyStrategy& other : s.strategies)
      if (other.kind == st.kind) top.fail(key, "strategy '" + st.kind + "' is listed twice");
    s.strategies.push_back(st);
  }

  const nlohmann::json& seeds = top.list("seeds", 1, 100000);
  for (size_t i = 0; i < seeds.size(); ++i) {
    const std::string key = "seeds[" + std::to_string(i) + "]";
    if (!seeds[i].is_number_integer() || seeds[i].get<long long>() < 0 || seeds[i].get<long long>() > 1000000000)
      top.fail(key, "expected an integer in [0, 1000000000]");
    const int seed = seeds[i].get<int>();
    if (std::find(s.seeds.begin(), s.seeds.end(), seed) != s.seeds.end())
      top.fail(key, "seed " + std::to_string(seed) + " is listed twice");
    s.seeds.push_back(seed);
  }
  if (top.has("duration_s")) s.duration_s = top.number("duration_s", 1e-3, 1e5);
  if (top.has("report")) {
    JsonObject r = top.object("report");
    if (r.has("shape_times_s")) s.shape_times_s = r.numbers("shape_times_s", 0.0, 1e5, 1, 20);
    r.finish();
  }
  top.ignore("note");
  top.finish();
  return s;
}

}  // namespace

Study parseStudy(const std::string& text, const std::string& file) {
  const nlohmann::json j = parseJsonText(text, file);
  Study s;
  try {
    s = studyFromJson(j, file);
  } catch (const InputError& e) {
    throw InputError(addLineToMessage(e.what(), file, text));
  }
  s.file_hash = hashBytes(text);
  return s;
}

Study loadStudy(const std::string& path) { return parseStudy(readTextFile(path), path); }

std::vector<StudyCase> studyCases(const Study& study) {
  std::vector<StudyCase> cases;
  for (int d = 0; d < static_cast<int>(study.designs.size()); ++d)
    for (int sc = 0; sc < static_cast<int>(study.scenarios.size()); ++sc)
      for (int st = 0; st < static_cast<int>(study.strategies.size()); ++st)
        for (int se = 0; se < static_cast<int>(study.seeds.size()); ++se) {
          StudyCase c;
          c.index = static_cast<int>(cases.size());
          c.design = d, c.scenario = sc, c.strategy = st, c.seed = se;
          cases.push_back(c);
        }
  return cases;
}

const std::vector<std::string>& studyMetricNames() {
  static const std::vector<std::string> names{
      "time_to_caecum_s",      "caecal_intubation_rate", "peak_wall_force_N",     "wall_force_integral_Ns",
      "peak_mesentery_stretch", "discomfort_index",      "loop_time_s",           "loop_writhe_max",
      "peak_handle_force_N",   "peak_handle_torque_Nm",  "shaft_movement_without_tip_progress_m"};
  return names;
}

// ---------------------------------------------------------------------------------------
// Seeds.

namespace {
// SplitMix64 (Steele, Lea & Flood 2014): a portable generator, so that a seed gives the
// same variant on every machine and standard library (std distributions do not).
uint64_t splitmix64(uint64_t& x) {
  uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
// Uniform in [-1, 1).
double symmetric(uint64_t& x) { return 2.0 * static_cast<double>(splitmix64(x) >> 11) * 0x1.0p-53 - 1.0; }
}  // namespace

SeedVariant seedVariant(int seed) {
  SeedVariant v;
  if (seed == 0) return v;
  uint64_t x = 0x636f6c6f73696dULL ^ static_cast<uint64_t>(seed);  // "colosim"
  v.operator_speed = 1.0 + 0.10 * symmetric(x);
  v.lifter_stiffness = 1.0 + 0.15 * symmetric(x);
  v.wall_friction = 1.0 + 0.15 * symmetric(x);
  return v;
}

// ---------------------------------------------------------------------------------------
// Running a case.

namespace {

// The case's parameters when they differ from the scenario's (a seed other than 0, an EI
// override); empty: the scenario's own, exactly as colosim run builds them.
std::optional<Parameters> caseParameters(const Study& study, const StudyCase& c, const Scenario& sc) {
  const StudyDesign& d = study.designs[c.design];
  const int seed = study.seeds[c.seed];
  if (seed == 0 && !d.shaft_bending_stiffness_Nm2) return std::nullopt;
  Parameters p = scenarioParameters(sc);
  if (d.shaft_bending_stiffness_Nm2) {  // uniform along the length, replacing the design's profile's EI
    p.scope.bending_stiffness_Nm2 = *d.shaft_bending_stiffness_Nm2;
    for (StiffnessSection& section : p.scope.stiffness_profile)
      section.bending_stiffness_Nm2 = *d.shaft_bending_stiffness_Nm2;
  }
  const SeedVariant v = seedVariant(seed);
  for (auto& [name, m] : p.colon.mesentery) m.stiffness_N_per_m2 *= v.lifter_stiffness;
  p.contact.friction_coefficient *= v.wall_friction;
  return p;
}

double caseEnd_s(const Study& study, const StudyCase& c, const Scenario& sc) {
  const StudyStrategy& st = study.strategies[c.strategy];
  double end = st.kind == "lumen_following" ? st.end_s : sc.duration_s;
  if (study.duration_s > 0) end = std::min(end, study.duration_s);
  return end;
}

}  // namespace

Scenario caseScenario(const Study& study, const StudyCase& c) {
  Scenario sc = findScenario(study.scenarios[c.scenario]);
  const StudyDesign& design = study.designs[c.design];
  if (!design.scope_path.empty()) useScopeDesign(sc, design.scope_path);
  if (design.stiffness_level) {
    // The operator's stiffening: a keyframe at stiffen_from_s (the inputs in force then),
    // and the level held on every keyframe from there.
    const double t0 = design.stiffen_from_s;
    const auto at = std::find_if(sc.script.begin(), sc.script.end(), [t0](const Keyframe& k) { return k.t_s >= t0; });
    if (at == sc.script.end() || at->t_s != t0) {
      Keyframe k;
      k.t_s = t0;
      k.input = scriptedInput(sc.script, t0);
      sc.script.insert(at, k);
    }
    for (Keyframe& k : sc.script)
      if (k.t_s >= t0) k.input.stiffness_level = *design.stiffness_level;
  }
  const SeedVariant v = seedVariant(study.seeds[c.seed]);
  if (v.operator_speed != 1.0) {
    // The operator's pace: the script after the scored start runs operator_speed times
    // faster (time-warped about the start), and so do the abdominal pressure and the turns.
    const double t0 = sc.scoring.start_s, f = v.operator_speed;
    auto warp = [t0, f](double t) { return t <= t0 ? t : t0 + (t - t0) / f; };
    for (Keyframe& k : sc.script) k.t_s = warp(k.t_s);
    for (AbdominalPressure& a : sc.abdominal_pressure) a.from_s = warp(a.from_s), a.to_s = warp(a.to_s);
    for (PatientTurn& turn : sc.patient_turns) turn.at_s = warp(turn.at_s);
    sc.duration_s = warp(sc.duration_s);
  }
  return sc;
}

long caseSteps(const Study& study, const StudyCase& c) {
  const Scenario sc = caseScenario(study, c);
  return std::lround(caseEnd_s(study, c, sc) / sc.dt_s);
}

CaseResult runStudyCase(const Study& study, const StudyCase& c, const std::function<void(long)>& on_steps) {
  Scenario sc = caseScenario(study, c);
  const std::optional<Parameters> params = caseParameters(study, c, sc);
  const std::unique_ptr<WorldSimulation> owned =
      params ? std::make_unique<WorldSimulation>(sc, *params) : std::make_unique<WorldSimulation>(sc);
  WorldSimulation& sim = *owned;
  const double dt_s = sim.dt_s();
  const double end_s = caseEnd_s(study, c, sc);
  CaseResult r;
  r.index = c.index;
  r.shapes_m.resize(study.shape_times_s.size());
  const long every = std::max(1L, std::lround(1.0 / (kStudyTimelineHz * dt_s)));
  long done = 0, reported = 0;
  auto record = [&](const Telemetry& t) {
    ++done;
    if (done % every == 0) {
      r.time_s.push_back(t.time_s);
      r.wall_force_total_N.push_back(t.wall_force_total_N);
      r.handle_force_N.push_back(t.handle_force_N);
    }
    for (size_t i = 0; i < study.shape_times_s.size(); ++i)
      if (done == std::lround(study.shape_times_s[i] / dt_s)) r.shapes_m[i] = sim.scopeCentreline();
    if (on_steps && done % 1000 == 0) on_steps(done - reported), reported = done;
  };
  nlohmann::json scores;
  if (study.strategies[c.strategy].kind == "scripted") {
    RunHooks hooks;
    hooks.on_step = record;
    const RunResult run = runScenario(sc, sim, nullptr, hooks, std::lround(end_s / dt_s));
    scores = run.scores;
  } else {
    Scorer scorer(sc.scoring);
    LumenFollowingOptions o;
    o.speed_m_per_s *= seedVariant(study.seeds[c.seed]).operator_speed;
    if (study.designs[c.design].stiffness_level) {
      o.stiffness_level = *study.designs[c.design].stiffness_level;
      o.stiffen_from_s = study.designs[c.design].stiffen_from_s;
    }
    LumenFollowingHooks hooks;
    hooks.on_step = [&](const WorldSimulation& s) {
      const Telemetry t = s.telemetry();
      scorer.add(t);
      record(t);
    };
    runLumenFollowing(sc, sim, sc.scoring.start_s, end_s, o, hooks);
    scores = scorer.json();
  }
  if (on_steps && done > reported) on_steps(done - reported);
  r.steps = done;
  r.final_state_hash = sim.stateHash();
  auto value = [&](const char* key) -> std::optional<double> {
    const nlohmann::json& v = scores.at(key);
    if (v.is_null()) return std::nullopt;
    return v.get<double>();
  };
  const std::optional<double> ttc = value("time_to_caecum_s");
  r.metrics = {ttc,
               ttc ? 1.0 : 0.0,
               value("peak_wall_force_total_N"),
               value("wall_force_integral_Ns"),
               value("peak_mesentery_stretch"),
               value("discomfort_index"),
               value("loop_time_s"),
               value("loop_writhe_max"),
               value("peak_handle_force_N"),
               value("peak_handle_torque_Nm"),
               value("shaft_movement_without_tip_progress_m")};
  return r;
}

std::vector<CaseResult> runStudyCases(const Study& study, const std::vector<StudyCase>& cases, int threads,
                                      const std::function<void(long, long)>& on_progress) {
  long total = 0;
  for (const StudyCase& c : cases) total += caseSteps(study, c);
  std::vector<CaseResult> results(cases.size());
  std::atomic<size_t> next{0};
  std::atomic<long> done{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto worker = [&] {
    for (size_t i; (i = next++) < cases.size();) {
      try {
        results[i] = runStudyCase(study, cases[i], [&](long steps) {
          const long d = done += steps;
          if (on_progress) on_progress(d, total);
        });
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = cases.size();
      }
    }
  };
  threads = std::max(1, std::min<int>(threads, static_cast<int>(cases.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  if (on_progress) on_progress(total, total);
  return results;
}

// ---------------------------------------------------------------------------------------
// Statistics.

MeanSd meanSd(const std::vector<double>& v) {
  MeanSd m;
  m.n = static_cast<int>(v.size());
  if (v.empty()) return m;
  double sum = 0;
  for (double x : v) sum += x;
  const double mean = sum / static_cast<double>(v.size());
  m.mean = mean;
  if (v.size() >= 2) {
    double ss = 0;
    for (double x : v) ss += (x - mean) * (x - mean);
    m.sd = std::sqrt(ss / static_cast<double>(v.size() - 1));
  }
  return m;
}

double studentT975(int dof) {
  // Exact table to 30 degrees of freedom (to 4 decimals and beyond), then the
  // Cornish-Fisher expansion around the normal quantile (error < 1e-6 past 30).
  static const double table[] = {12.706204736, 4.302652730, 3.182446305, 2.776445105, 2.570581836, 2.446911851,
                                 2.364624252,  2.306004135, 2.262157163, 2.228138852, 2.200985160, 2.178812830,
                                 2.160368656,  2.144786688, 2.131449546, 2.119905299, 2.109815578, 2.100922040,
                                 2.093024054,  2.085963447, 2.079613845, 2.073873068, 2.068657610, 2.063898562,
                                 2.059538553,  2.055529439, 2.051830516, 2.048407142, 2.045229642, 2.042272456};
  if (dof < 1) return NAN;
  if (dof <= 30) return table[dof - 1];
  const double z = 1.959963984540054, n = dof;
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z, z9 = z7 * z * z;
  return z + (z3 + z) / (4 * n) + (5 * z5 + 16 * z3 + 3 * z) / (96 * n * n) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * n * n * n) +
         (79 * z9 + 776 * z7 + 1482 * z5 - 1920 * z3 - 945 * z) / (92160 * n * n * n * n);
}

PairedDifference pairedDifference(const std::vector<double>& d) {
  PairedDifference p;
  const MeanSd m = meanSd(d);
  p.n = m.n;
  p.mean_difference = m.mean;
  if (m.sd) {
    const double half = studentT975(m.n - 1) * *m.sd / std::sqrt(static_cast<double>(m.n));
    p.ci95 = std::make_pair(*m.mean - half, *m.mean + half);
  }
  return p;
}

// ---------------------------------------------------------------------------------------
// Summaries.

namespace {

nlohmann::ordered_json orNull(const std::optional<double>& x) {
  return x ? nlohmann::ordered_json(*x) : nlohmann::ordered_json(nullptr);
}

int casesPerDesign(const StudyResults& r) { return r.scenarios * r.strategies * r.seeds; }

// Values of metric m for design d, and the paired differences against design 0.
void collect(const StudyResults& r, int d, size_t m, std::vector<double>& values, std::vector<double>& diffs) {
  const int per = casesPerDesign(r);
  values.clear(), diffs.clear();
  for (int k = 0; k < per; ++k) {
    const std::optional<double>& x = r.cases[static_cast<size_t>(d * per + k)].metrics[m];
    const std::optional<double>& ref = r.cases[static_cast<size_t>(k)].metrics[m];
    if (x) values.push_back(*x);
    if (x && ref) diffs.push_back(*x - *ref);
  }
}

}  // namespace

StudyResults studyResults(const Study& study, std::vector<CaseResult> results) {
  StudyResults r;
  r.study = study.name;
  r.study_hash = study.file_hash;
  for (const StudyDesign& d : study.designs) r.designs.push_back(d.name);
  r.scenarios = static_cast<int>(study.scenarios.size());
  r.strategies = static_cast<int>(study.strategies.size());
  r.seeds = static_cast<int>(study.seeds.size());
  r.cases = std::move(results);
  return r;
}

nlohmann::ordered_json studySummaryJson(const StudyResults& r) {
  nlohmann::ordered_json out;
  out["study"] = r.study;
  out["designs"] = nlohmann::ordered_json::array();
  const std::vector<std::string>& names = studyMetricNames();
  std::vector<double> values, diffs;
  for (int d = 0; d < static_cast<int>(r.designs.size()); ++d) {
    nlohmann::ordered_json design;
    design["name"] = r.designs[static_cast<size_t>(d)];
    design["cases"] = casesPerDesign(r);
    nlohmann::ordered_json metrics = nlohmann::ordered_json::object(), vs = nlohmann::ordered_json::object();
    for (size_t m = 0; m < names.size(); ++m) {
      collect(r, d, m, values, diffs);
      const MeanSd ms = meanSd(values);
      metrics[names[m]] = {{"mean", orNull(ms.mean)}, {"sd", orNull(ms.sd)}};
      const PairedDifference p = pairedDifference(diffs);
      nlohmann::ordered_json ci = nullptr;
      if (p.ci95) ci = nlohmann::ordered_json::array({p.ci95->first, p.ci95->second});
      vs[names[m]] = {{"mean_difference", orNull(p.mean_difference)}, {"ci95", ci}};
    }
    design["metrics"] = metrics;
    design["vs_first"] = vs;
    out["designs"].push_back(design);
  }
  return out;
}

std::string studySummaryText(const StudyResults& r, const std::vector<std::string>& case_labels) {
  (void)case_labels;
  std::ostringstream o;
  char buf[512];
  const std::vector<std::string>& names = studyMetricNames();
  const int per = casesPerDesign(r);
  std::snprintf(buf, sizeof buf, "colosim study %s: %zu designs x %d cases (%d scenarios x %d strategies x %d seeds)\n",
                r.study.c_str(), r.designs.size(), per, r.scenarios, r.strategies, r.seeds);
  o << buf;
  auto num = [](const std::optional<double>& x) {
    char b[32];
    if (!x) return std::string("-");
    std::snprintf(b, sizeof b, "%.4g", *x);
    return std::string(b);
  };
  std::vector<double> values, diffs;
  for (int d = 0; d < static_cast<int>(r.designs.size()); ++d) {
    o << "\n  design " << r.designs[static_cast<size_t>(d)] << (d == 0 ? " (reference)" : "") << "\n";
    std::snprintf(buf, sizeof buf, "    %-40s %4s %10s %10s %12s  %s\n", "metric", "n", "mean", "sd",
                  d == 0 ? "" : "vs first", d == 0 ? "" : "95% CI (paired, t)");
    o << buf;
    for (size_t m = 0; m < names.size(); ++m) {
      collect(r, d, m, values, diffs);
      const MeanSd ms = meanSd(values);
      const PairedDifference p = pairedDifference(diffs);
      std::string ci;
      if (d > 0) ci = p.ci95 ? "[" + num(p.ci95->first) + ", " + num(p.ci95->second) + "]" : "-";
      std::snprintf(buf, sizeof buf, "    %-40s %4d %10s %10s %12s  %s\n", names[m].c_str(), ms.n,
                    num(ms.mean).c_str(), num(ms.sd).c_str(), d == 0 ? "" : num(p.mean_difference).c_str(),
                    ci.c_str());
      o << buf;
    }
  }
  o << "\n  time_to_caecum_s is over the cases that reach the caecum (n); '-': no value "
       "(docs/design-studies.md)\n";
  return o.str();
}

// ---------------------------------------------------------------------------------------
// Shards.

std::vector<StudyCase> shardCases(const std::vector<StudyCase>& all, int k, int n) {
  std::vector<StudyCase> out;
  for (const StudyCase& c : all)
    if (c.index % n == k - 1) out.push_back(c);
  return out;
}

std::pair<int, int> parseShard(const std::string& text) {
  const size_t slash = text.find('/');
  auto bad = [&]() -> InputError {
    return InputError("--shard " + text + ": expected K/N with 1 <= K <= N (for example 2/8)");
  };
  if (slash == std::string::npos) throw bad();
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  auto digits = [](const std::string& s) {
    return !s.empty() && s.size() <= 6 && std::all_of(s.begin(), s.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
  };
  if (!digits(a) || !digits(b)) throw bad();
  const int k = std::stoi(a), n = std::stoi(b);
  if (k < 1 || n < 1 || k > n) throw bad();
  return {k, n};
}

namespace {
std::string shardName(int k, int n) { return "shard-" + std::to_string(k) + "-of-" + std::to_string(n) + ".json"; }
}  // namespace

std::string writeShard(const Study& study, int k, int n, const std::vector<StudyCase>& cases,
                       const std::vector<CaseResult>& results, const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw InputError(dir + ": cannot create the folder");
  const std::string path = (fs::path(dir) / shardName(k, n)).string();
  if (fs::exists(path, ec)) throw InputError(path + ": exists (a shard is never overwritten)");
  nlohmann::ordered_json j;
  j["format"] = "colosim-study-shard";
  j["version"] = 1;
  j["study"] = study.name;
  j["study_file"] = study.file;
  j["study_hash"] = hashToHex(study.file_hash);
  j["designs"] = nlohmann::ordered_json::array();
  for (const StudyDesign& d : study.designs) j["designs"].push_back(d.name);
  j["scenarios"] = static_cast<int>(study.scenarios.size());
  j["strategies"] = static_cast<int>(study.strategies.size());
  j["seeds"] = static_cast<int>(study.seeds.size());
  j["shard"] = k;
  j["shards"] = n;
  j["cases"] = nlohmann::ordered_json::array();
  const std::vector<std::string>& names = studyMetricNames();
  for (size_t i = 0; i < cases.size(); ++i) {
    const StudyCase& c = cases[i];
    const CaseResult& r = results[i];
    nlohmann::ordered_json cj;
    cj["index"] = c.index;
    cj["design"] = study.designs[c.design].name;
    cj["scenario"] = study.scenarios[c.scenario];
    cj["strategy"] = study.strategies[c.strategy].kind;
    cj["seed"] = study.seeds[c.seed];
    cj["steps"] = r.steps;
    cj["final_state_hash"] = hashToHex(r.final_state_hash);
    nlohmann::ordered_json m = nlohmann::ordered_json::object();
    for (size_t k2 = 0; k2 < names.size(); ++k2) m[names[k2]] = orNull(r.metrics[k2]);  // shortest round-trip text
    cj["metrics"] = m;
    j["cases"].push_back(cj);
  }
  // Written to a temporary name and renamed: a shard file is whole or absent.
  const std::string tmp = path + ".part";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << j.dump(1) << "\n";
    if (!out) throw InputError(tmp + ": cannot write");
  }
  fs::rename(tmp, path, ec);
  if (ec) throw InputError(path + ": cannot write (" + ec.message() + ")");
  return path;
}

StudyResults mergeShards(const std::vector<std::string>& dirs) {
  std::vector<std::string> files;
  for (const std::string& dir : dirs) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(dir + ": not a folder (--merge takes the folders given to --out)");
    std::vector<std::string> here;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      if (name.rfind("shard-", 0) == 0 && e.path().extension() == ".json") here.push_back(e.path().string());
    }
    if (here.empty()) throw InputError(dir + ": no shard files (shard-K-of-N.json) in it");
    std::sort(here.begin(), here.end());
    files.insert(files.end(), here.begin(), here.end());
  }
  StudyResults r;
  std::string first_file;
  int shards = 0;
  std::set<int> shards_seen;
  std::vector<std::string> case_file;  // which file gave each case
  const std::vector<std::string>& names = studyMetricNames();
  for (const std::string& file : files) {
    const std::string text = readTextFile(file);
    const nlohmann::json j = parseJsonText(text, file);
    try {
      JsonObject top(j, file);
      top.formatAndVersion("colosim-study-shard");
      const std::string study = top.string("study");
      top.ignore("study_file");
      const std::string hash = top.string("study_hash");
      std::vector<std::string> designs;
      const nlohmann::json& dl = top.raw("designs");
      if (!dl.is_array() || dl.empty()) top.fail("designs", "expected a list of design names");
      for (const auto& d : dl) {
        if (!d.is_string()) top.fail("designs", "expected a list of design names");
        designs.push_back(d.get<std::string>());
      }
      const int scenarios = top.integer("scenarios", 1, 1000), strategies = top.integer("strategies", 1, 100);
      const int seeds = top.integer("seeds", 1, 100000);
      const int n = top.integer("shards", 1, 1000000);
      const int k = top.integer("shard", 1, n);
      if (first_file.empty()) {
        first_file = file;
        r.study = study;
        r.designs = designs;
        r.scenarios = scenarios, r.strategies = strategies, r.seeds = seeds;
        shards = n;
        r.study_hash = std::stoull(hash, nullptr, 16);
        r.cases.resize(designs.size() * static_cast<size_t>(scenarios * strategies * seeds));
        case_file.resize(r.cases.size());
      } else if (hash != hashToHex(r.study_hash) || study != r.study || designs != r.designs ||
                 scenarios != r.scenarios || strategies != r.strategies || seeds != r.seeds) {
        top.fail("study_hash", "from another study than " + first_file + " (study '" + study + "' " + hash +
                                   ", there '" + r.study + "' " + hashToHex(r.study_hash) + ")");
      } else if (n != shards) {
        top.fail("shards", "split into " + std::to_string(n) + " shards, " + first_file + " into " +
                               std::to_string(shards));
      }
      if (!shards_seen.insert(k).second) top.fail("shard", "shard " + std::to_string(k) + " is given twice");
      const nlohmann::json& cl = top.raw("cases");
      if (!cl.is_array()) top.fail("cases", "expected a list");
      for (size_t i = 0; i < cl.size(); ++i) {
        JsonObject c(cl[i], file, "cases[" + std::to_string(i) + "]");
        const int index = c.integer("index", 0, static_cast<int>(r.cases.size()) - 1);
        if (index % n != k - 1) c.fail("index", "case " + std::to_string(index) + " does not belong to shard " +
                                                    std::to_string(k) + "/" + std::to_string(n));
        if (!case_file[static_cast<size_t>(index)].empty())
          c.fail("index", "case " + std::to_string(index) + " is also in " + case_file[static_cast<size_t>(index)]);
        case_file[static_cast<size_t>(index)] = file;
        c.ignore("design"), c.ignore("scenario"), c.ignore("strategy"), c.ignore("seed");
        CaseResult cr;
        cr.index = index;
        cr.steps = c.raw("steps").get<long>();
        cr.final_state_hash = std::stoull(c.string("final_state_hash"), nullptr, 16);
        JsonObject m = c.object("metrics");
        for (const std::string& name : names) {
          const nlohmann::json& v = m.raw(name);
          if (v.is_null()) cr.metrics.push_back(std::nullopt);
          else if (v.is_number() && std::isfinite(v.get<double>())) cr.metrics.push_back(v.get<double>());
          else m.fail(name, "expected a number or null");
        }
        m.finish();
        c.finish();
        r.cases[static_cast<size_t>(index)] = cr;
      }
      top.finish();
    } catch (const InputError& e) {
      throw InputError(addLineToMessage(e.what(), file, text));
    } catch (const std::exception& e) {
      throw InputError(file + ": not a shard file (" + e.what() + ")");
    }
  }
  std::string missing;
  int missing_count = 0;
  for (size_t i = 0; i < case_file.size(); ++i)
    if (case_file[i].empty() && ++missing_count <= 10) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
  if (missing_count > 0) {
    std::string absent;
    for (int k = 1; k <= shards; ++k)
      if (!shards_seen.count(k)) absent += (absent.empty() ? "" : ", ") + shardName(k, shards);
    throw InputError("study '" + r.study + "': " + std::to_string(missing_count) + " of " +
                     std::to_string(case_file.size()) + " cases missing (" + missing + (missing_count > 10 ? ", ..." : "") +
                     ")" + (absent.empty() ? "" : "; shard files not found: " + absent));
  }
  return r;
}

}  // namespace colosim

// ---------------------------------------------------------------------------------------
// Report.

namespace colosim {

namespace {

// A file name part from a design name: letters, digits, '-' and '_' kept, others '_'.
std::string fileSafe(const std::string& name) {
  std::string out = name;
  for (char& ch : out)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '_';
  return out;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::trunc);
  out << text;
  if (!out) throw InputError(path + ": cannot write");
}

bool haveGnuplot() { return std::system("gnuplot --version > /dev/null 2>&1") == 0; }

}  // namespace

std::vector<std::string> writeStudyReport(const Study& study, const std::vector<StudyCase>& cases,
                                          const std::vector<CaseResult>& results, const std::string& dir) {
  std::vector<std::string> lines;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw InputError(dir + ": cannot create the report folder");
  const std::vector<std::string>& names = studyMetricNames();
  const fs::path root(dir);
  std::vector<std::string> gp_files;
  char buf[256];

  // 1. Per-case metrics (one row per case; '?' for no value, which gnuplot skips).
  {
    std::ostringstream o;
    o << "# colosim study " << study.name << ": one row per case; ? = no value\n# design_index design scenario strategy seed";
    for (const std::string& n : names) o << " " << n;
    o << "\n";
    for (size_t i = 0; i < cases.size(); ++i) {
      const StudyCase& c = cases[i];
      o << c.design << " " << fileSafe(study.designs[c.design].name) << " "
        << fileSafe(fs::path(study.scenarios[c.scenario]).stem().string()) << " " << study.strategies[c.strategy].kind
        << " " << study.seeds[c.seed];
      for (const std::optional<double>& m : results[i].metrics) {
        if (m) std::snprintf(buf, sizeof buf, " %.17g", *m);
        o << (m ? std::string(buf) : std::string(" ?"));
      }
      o << "\n";
    }
    writeText((root / "metrics.dat").string(), o.str());
  }
  std::string xtics;
  for (size_t d = 0; d < study.designs.size(); ++d)
    xtics += (d ? ", " : "") + std::string("\"") + study.designs[d].name + "\" " + std::to_string(d);
  {
    std::ostringstream g;
    g << "# Per-design distributions of the case metrics (metrics.dat): every case a point.\nset terminal pngcairo size 800,500\nset datafile missing '?'\n"
         "set xtics (" << xtics << ")\nset xrange [-0.5:" << study.designs.size() - 0.5 << "]\nset key off\nset grid y\n";
    for (size_t m = 0; m < names.size(); ++m) {
      bool any = false;  // gnuplot stops at a plot without points
      for (const CaseResult& r : results) any = any || r.metrics[m].has_value();
      if (!any) {
        g << "# " << names[m] << ": no case has a value\n";
        continue;
      }
      g << "set output 'metric_" << names[m] << ".png'\nset title '" << study.name << ": " << names[m]
        << " per design (each case a point)' noenhanced\nset ylabel '" << names[m] << "' noenhanced\n"
        << "plot 'metrics.dat' using ($1 + 0.05 * ((int($5) % 7) - 3)):" << (m + 6) << " with points pt 7 ps 1\n";
    }
    writeText((root / "distributions.gp").string(), g.str());
    gp_files.push_back("distributions.gp");
  }

  // 2. Force timelines: per design, the mean over its cases at each sample time.
  {
    std::ostringstream g;
    g << "# Wall and handle force over time, per design (the mean over the design's cases at each time).\n"
         "set terminal pngcairo size 900,500\nset grid\nset key outside right noenhanced\nset xlabel 'time [s]'\n";
    std::string wall_plot, handle_plot;
    for (size_t d = 0; d < study.designs.size(); ++d) {
      std::map<long, std::array<double, 3>> sums;  // sample -> (wall, handle, count)
      std::map<long, double> t_of;
      for (size_t i = 0; i < cases.size(); ++i) {
        if (cases[i].design != static_cast<int>(d)) continue;
        const CaseResult& r = results[i];
        for (size_t k = 0; k < r.time_s.size(); ++k) {
          auto& acc = sums[static_cast<long>(k)];
          acc[0] += r.wall_force_total_N[k], acc[1] += r.handle_force_N[k], acc[2] += 1;
          t_of[static_cast<long>(k)] = r.time_s[k];
        }
      }
      std::ostringstream o;
      o << "# design " << study.designs[d].name << ": time_s mean_wall_force_total_N mean_handle_force_N cases\n";
      for (const auto& [k, acc] : sums) {
        std::snprintf(buf, sizeof buf, "%.4f %.6g %.6g %d\n", t_of[k], acc[0] / acc[2], acc[1] / acc[2],
                      static_cast<int>(acc[2]));
        o << buf;
      }
      const std::string file = "timeline_" + fileSafe(study.designs[d].name) + ".dat";
      writeText((root / file).string(), o.str());
      wall_plot += (d ? ", " : "") + std::string("'") + file + "' using 1:2 with lines title '" + study.designs[d].name + "'";
      handle_plot +=
          (d ? ", " : "") + std::string("'") + file + "' using 1:3 with lines title '" + study.designs[d].name + "'";
    }
    g << "set output 'wall_force.png'\nset title 'total scope-wall contact force (mean over cases)'\n"
         "set ylabel 'force [N]'\nplot " << wall_plot << "\n";
    g << "set output 'handle_force.png'\nset title 'handle force, + = push (mean over cases)'\n"
         "set ylabel 'force [N]'\nplot " << handle_plot << "\n";
    writeText((root / "forces.gp").string(), g.str());
    gp_files.push_back("forces.gp");
  }

  // 3. Scope shapes at the chosen times (coronal projection: x to the patient's left, z
  // cranial), from each design's first case, over the colon's rest centreline.
  if (!study.shape_times_s.empty()) {
    std::ostringstream g;
    g << "# Scope shapes (coronal projection, x: patient's left, z: cranial) of each design's first case.\n"
         "set terminal pngcairo size 700,700\nset size ratio -1\nset grid\nset key outside right noenhanced\n"
         "set xlabel 'x (patient left) [m]'\nset ylabel 'z (cranial) [m]'\n";
    for (size_t ti = 0; ti < study.shape_times_s.size(); ++ti) {
      std::string plot;
      for (size_t i = 0; i < cases.size(); ++i) {
        const StudyCase& c = cases[i];
        if (c.scenario != 0 || c.strategy != 0 || c.seed != 0) continue;
        const std::vector<Vec3>& shape = results[i].shapes_m[ti];
        if (shape.empty()) continue;
        std::snprintf(buf, sizeof buf, "shape_%s_t%g.dat", fileSafe(study.designs[c.design].name).c_str(),
                      study.shape_times_s[ti]);
        std::ostringstream o;
        o << "# scope centreline at t = " << study.shape_times_s[ti] << " s, design " << study.designs[c.design].name
          << ": x_m y_m z_m\n";
        for (const Vec3& p : shape) {
          char row[128];
          std::snprintf(row, sizeof row, "%.6f %.6f %.6f\n", p.x(), p.y(), p.z());
          o << row;
        }
        writeText((root / buf).string(), o.str());
        plot += (plot.empty() ? "" : ", ") + std::string("'") + buf + "' using 1:3 with lines lw 2 title '" +
                study.designs[c.design].name + "'";
      }
      if (plot.empty()) continue;
      std::snprintf(buf, sizeof buf, "shape_t%g.png", study.shape_times_s[ti]);
      g << "set output '" << buf << "'\nset title 'scope at t = " << study.shape_times_s[ti] << " s'\nplot " << plot
        << "\n";
    }
    writeText((root / "shapes.gp").string(), g.str());
    gp_files.push_back("shapes.gp");
  }

  lines.push_back("report data and gnuplot scripts written in " + dir);
  if (!haveGnuplot()) {
    lines.push_back("gnuplot not found: PNGs skipped (install gnuplot-nox, then run gnuplot on the .gp files in " +
                    dir + ")");
    return lines;
  }
  for (const std::string& gp : gp_files) {
    // gnuplot's messages go to the report's gnuplot.log, never to stdout (--json).
    const std::string cmd = "cd '" + dir + "' && gnuplot " + gp + (gp == gp_files.front() ? " >" : " >>") +
                            " gnuplot.log 2>&1";
    if (std::system(cmd.c_str()) != 0) lines.push_back("gnuplot failed on " + gp + " (see gnuplot.log)");
  }
  lines.push_back("PNGs drawn by gnuplot in " + dir);
  return lines;
}

}  // namespace colosim
