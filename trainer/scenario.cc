#include "trainer/scenario.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "trainer/assets.h"
#include "trainer/handle_io.h"
#include "trainer/json_position.h"
#include "trainer/scope_design.h"
#include "trainer/strict_json.h"

namespace colosim {

namespace fs = std::filesystem;

long Scenario::steps() const { return std::lround(duration_s / dt_s); }

namespace {

// An asset path as written in a scenario: relative to assets/ (or absolute).
std::string assetFile(JsonObject& top, const std::string& key) {
  const std::string rel = top.string(key);
  if (rel.empty()) top.fail(key, "must not be empty");
  const std::string path = (!rel.empty() && rel[0] == '/') ? rel : assetPath(rel);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) top.fail(key, "no such file: " + path + " (paths are relative to " + assetDir() + ")");
  return path;
}

Scenario scenarioFromJson(const nlohmann::json& j, const std::string& path) {
  JsonObject top(j, path);
  top.formatAndVersion("colosim-scenario");

  Scenario s;
  s.file = path;
  s.name = top.string("name");
  if (s.name.empty()) top.fail("name", "must not be empty");
  s.description = top.string("description");
  if (top.has("goal")) {
    s.goal = top.string("goal");
    if (s.goal.empty() || s.goal.size() > 4000) top.fail("goal", "expected 1 to 4000 characters");
  }
  s.anatomy_path = assetFile(top, "anatomy");
  s.params_path = assetFile(top, "params");
  s.scope_path = top.has("scope") ? assetFile(top, "scope") : assetPath(kDefaultScopeDesign);
  s.dt_s = top.number("dt_s", 1e-5, 1e-2);
  s.duration_s = top.number("duration_s", 1e-3, 1e5);
  s.seed = top.integer("seed", 0, INT_MAX);

  JsonObject start = top.object("start");
  s.start.kind = start.choice("kind", {"rest", "settled", "scripted"});
  if (s.start.kind == "settled") s.start.settle_s = start.number("settle_s", 0.0, 600.0);
  if (s.start.kind == "scripted") {
    s.start.until_s = start.number("until_s", 0.0, s.duration_s);
    s.scoring.start_s = s.start.until_s;
  }
  if (start.has("colon_shape")) {
    JsonObject shape = start.object("colon_shape");
    s.start.shape_region = shape.string("region");
    if (s.start.shape_region.empty()) shape.fail("region", "must not be empty");
    const nlohmann::json& pts = shape.raw("points_m");
    if (!pts.is_array() || pts.size() < 4 || pts.size() > 1000)
      shape.fail("points_m", "expected a list of 4 to 1000 [x, y, z] points");
    for (size_t k = 0; k < pts.size(); ++k) {
      const std::string key = "points_m[" + std::to_string(k) + "]";
      if (!pts[k].is_array() || pts[k].size() != 3) shape.fail(key, "expected [x, y, z] in metres");
      Vec3 p;
      for (int d = 0; d < 3; ++d) {
        if (!pts[k][d].is_number() || !std::isfinite(pts[k][d].get<double>()))
          shape.fail(key, "coordinates must be finite numbers");
        p(d) = pts[k][d].get<double>();
        if (std::abs(p(d)) > 2.0) shape.fail(key, "coordinate out of range [-2, 2] m (wrong unit?)");
      }
      if (!s.start.shape_points_m.empty() && (p - s.start.shape_points_m.back()).norm() < 1e-4)
        shape.fail(key, "closer than 0.1 mm to the previous point");
      s.start.shape_points_m.push_back(p);
    }
    shape.ignore("note");
    shape.finish();
  }
  start.ignore("note");
  start.finish();

  if (top.has("overrides")) {
    JsonObject o = top.object("overrides");
    if (o.has("wall_friction")) s.overrides.wall_friction = o.number("wall_friction", 0.0, 2.0);
    if (o.has("colon_axial_rigidity_N"))
      s.overrides.colon_axial_rigidity_N = o.number("colon_axial_rigidity_N", 1.0, 1e5);
    if (o.has("patient_position"))
      s.overrides.patient_position = o.choice("patient_position", patientPositions());
    o.finish();
  }

  if (top.has("abdominal_pressure")) {
    const nlohmann::json& list = top.raw("abdominal_pressure");
    if (!list.is_array() || list.empty() || list.size() > 100)
      top.fail("abdominal_pressure", "expected a list of 1 to 100 pressures");
    for (size_t i = 0; i < list.size(); ++i) {
      JsonObject a(list[i], path, "abdominal_pressure[" + std::to_string(i) + "]");
      AbdominalPressure ap;
      ap.region = a.string("region");
      if (ap.region.empty()) a.fail("region", "must not be empty");
      ap.from_s = a.number("from_s", 0.0, s.duration_s);
      ap.to_s = a.number("to_s", 0.0, s.duration_s);
      if (!(ap.to_s > ap.from_s)) a.fail("to_s", "must be after from_s (" + std::to_string(ap.from_s) + " s)");
      if (a.has("ramp_s")) ap.ramp_s = a.number("ramp_s", 0.0, 60.0);
      ap.stiffness_N_per_m2 = a.number("stiffness_N_per_m2", 0.0, 1e5);
      ap.damping_Ns_per_m2 = a.number("damping_Ns_per_m2", 0.0, 1e4);
      a.ignore("note");
      a.finish();
      s.abdominal_pressure.push_back(ap);
    }
  }

  if (top.has("patient_turns")) {
    const nlohmann::json& list = top.raw("patient_turns");
    if (!list.is_array() || list.empty() || list.size() > 100)
      top.fail("patient_turns", "expected a list of 1 to 100 turns");
    for (size_t i = 0; i < list.size(); ++i) {
      JsonObject a(list[i], path, "patient_turns[" + std::to_string(i) + "]");
      PatientTurn turn;
      turn.at_s = a.number("at_s", 0.0, s.duration_s);
      if (!s.patient_turns.empty() && !(turn.at_s > s.patient_turns.back().at_s))
        a.fail("at_s", "must be after the previous turn's (" + std::to_string(s.patient_turns.back().at_s) + " s)");
      turn.position = a.choice("position", patientPositions());
      a.ignore("note");
      a.finish();
      s.patient_turns.push_back(turn);
    }
  }

  if (top.has("scoring")) {
    JsonObject sc = top.object("scoring");
    ScoreOptions& so = s.scoring;
    if (sc.has("caecum_reach_m")) so.caecum_reach_m = sc.number("caecum_reach_m", 1e-3, 0.5);
    if (sc.has("excessive_wall_force_N")) so.excessive_wall_force_N = sc.number("excessive_wall_force_N", 0.0, 1e3);
    if (sc.has("episode_min_s")) so.episode_min_s = sc.number("episode_min_s", 0.0, 60.0);
    if (sc.has("discomfort_strain")) so.discomfort_strain = sc.number("discomfort_strain", 0.0, 10.0);
    if (sc.has("discomfort_stretch")) so.discomfort_stretch = sc.number("discomfort_stretch", 0.0, 1e3);
    if (sc.has("loop_turns")) so.loop_turns = sc.number("loop_turns", 0.0, 100.0);
    if (sc.has("patch_seen_min_s")) so.patch_seen_min_s = sc.number("patch_seen_min_s", 0.0, 60.0);
    if (sc.has("high_handle_force_N")) so.high_handle_force_N = sc.number("high_handle_force_N", 0.0, 1e3);
    sc.finish();
  }

  const nlohmann::json& script = top.raw("script");
  if (!script.is_array() || script.empty()) top.fail("script", "expected a non-empty list of keyframes");
  for (size_t i = 0; i < script.size(); ++i) {
    JsonObject k(script[i], path, "script[" + std::to_string(i) + "]");
    Keyframe f;
    f.t_s = k.number("t_s", 0.0, s.duration_s);
    if (i == 0 && f.t_s != 0.0) k.fail("t_s", "the first keyframe must be at t_s = 0");
    if (i > 0 && !(f.t_s > s.script.back().t_s))
      k.fail("t_s", "keyframe times must increase strictly (previous: " + std::to_string(s.script.back().t_s) + " s)");
    f.input = readHandleInput(k);
    k.ignore("note");
    k.finish();
    s.script.push_back(f);
  }
  top.finish();
  return s;
}

// The folders a scenario is found in by its name: the training scenarios, then the
// identification bench's specimens (scenarios/bench/: not training scenarios, so not in
// shippedScenarioNames; docs/organ-identification.md).
std::array<fs::path, 2> namedScenarioDirs() {
  const fs::path scenarios = fs::path(assetDir()) / "scenarios";
  return {scenarios, scenarios / "bench"};
}

}  // namespace

Scenario parseScenario(const std::string& text, const std::string& path) {
  const nlohmann::json j = parseJsonText(text, path);  // syntax errors carry their line
  Scenario s;
  try {
    s = scenarioFromJson(j, path);
  } catch (const InputError& e) {
    throw InputError(addLineToMessage(e.what(), path, text));
  }
  s.file_hash = hashBytes(text);
  return s;
}

Scenario loadScenario(const std::string& path) {
  Scenario s = parseScenario(readTextFile(path), path);
  // A shipped scenario (or bench specimen) is named by its name, so that sessions and
  // recordings replay on other machines.
  std::error_code ec;
  s.id = fs::absolute(path).lexically_normal().string();
  for (const fs::path& dir : namedScenarioDirs())
    if (fs::equivalent(dir / (s.name + ".json"), path, ec)) s.id = s.name;
  return s;
}

std::vector<std::string> shippedScenarioNames() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(assetDir()) / "scenarios", ec))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string resolveScenarioPath(const std::string& name_or_path) {
  std::error_code ec;
  if (fs::is_regular_file(name_or_path, ec)) return name_or_path;
  if (name_or_path.find('/') == std::string::npos && !name_or_path.empty()) {
    std::string file = name_or_path;
    if (fs::path(file).extension() != ".json") file += ".json";
    for (const fs::path& dir : namedScenarioDirs())
      if (fs::is_regular_file(dir / file, ec)) return (dir / file).string();
  }
  std::string list;
  for (const std::string& n : shippedScenarioNames()) list += (list.empty() ? "" : ", ") + n;
  throw InputError(name_or_path + ": no such scenario (not a file, nor one of the shipped scenarios: " + list + ")");
}

Scenario findScenario(const std::string& name_or_path) { return loadScenario(resolveScenarioPath(name_or_path)); }

HandleInput scriptedInput(const std::vector<Keyframe>& script, double t_s) {
  if (script.empty()) return HandleInput{};
  if (t_s <= script.front().t_s) return script.front().input;
  if (t_s >= script.back().t_s) return script.back().input;
  // First keyframe after t_s (the script is short: a binary search keeps it O(log n)).
  const auto it = std::upper_bound(script.begin(), script.end(), t_s,
                                   [](double t, const Keyframe& k) { return t < k.t_s; });
  const Keyframe& b = *it;
  const Keyframe& a = *(it - 1);
  const double w = (t_s - a.t_s) / (b.t_s - a.t_s);
  // Convex combinations stay within the keyframes' range; the clamp guards the last ulp
  // so that a recorded session never holds a value its reader would refuse.
  auto lerp = [w](double x, double y) { return std::clamp(x + w * (y - x), std::min(x, y), std::max(x, y)); };
  HandleInput in;
  in.insertion_m = lerp(a.input.insertion_m, b.input.insertion_m);
  in.rotation_rad = lerp(a.input.rotation_rad, b.input.rotation_rad);
  in.knob_updown_rad = lerp(a.input.knob_updown_rad, b.input.knob_updown_rad);
  in.knob_leftright_rad = lerp(a.input.knob_leftright_rad, b.input.knob_leftright_rad);
  in.stiffness_level = a.input.stiffness_level;  // held until the next keyframe, not interpolated
  return in;
}

InputError scenarioError(const std::string& file, const std::string& message) {
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return InputError(addLineToMessage(message, file, text));
}

Parameters scenarioParameters(const Scenario& scenario) {
  Parameters params = loadParameters(scenario.params_path);
  const ScopeDesign design = loadScopeDesign(scenario.scope_path);
  applyScopeDesign(design, params.scope);
  if (!scenario.params_replaced) params.contact.friction_coefficient = design.sheath_friction;
  if (scenario.overrides.patient_position) params.colon.patient_position = *scenario.overrides.patient_position;
  if (scenario.overrides.wall_friction) params.contact.friction_coefficient = *scenario.overrides.wall_friction;
  if (scenario.overrides.colon_axial_rigidity_N) {
    if (params.tension_law)
      throw scenarioError(scenario.file, scenario.file + ": overrides.colon_axial_rigidity_N: " + scenario.params_path +
                                             " carries a tension law (colon.tension_law) with its own EA");
    params.colon.tension_EA_N = *scenario.overrides.colon_axial_rigidity_N;
  }
  return params;
}

const std::vector<std::string>& patientPositions() {
  static const std::vector<std::string> positions{"left_lateral", "right_lateral", "supine", "prone"};
  return positions;
}

std::string nextPatientPosition(const std::string& position) {
  static const std::vector<std::string> order{"left_lateral", "supine", "right_lateral", "prone"};
  const auto it = std::find(order.begin(), order.end(), position);
  if (it == order.end())
    throw InputError("patient position '" + position + "': expected left_lateral, right_lateral, supine or prone");
  return order[(static_cast<size_t>(it - order.begin()) + 1) % order.size()];
}

std::string patientPositionOf(const Scenario& scenario) {
  if (scenario.overrides.patient_position) return *scenario.overrides.patient_position;
  return loadParameters(scenario.params_path).colon.patient_position;
}

void choosePatientPosition(Scenario& scenario, const std::string& position) {
  const std::vector<std::string>& all = patientPositions();
  if (std::find(all.begin(), all.end(), position) == all.end())
    throw InputError("patient position '" + position + "': expected left_lateral, right_lateral, supine or prone");
  scenario.overrides.patient_position = position;
  scenario.patient_position_chosen = true;
}

void useScopeDesign(Scenario& scenario, const std::string& scope_path) {
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(scope_path, ec);
  const std::string path = ec ? scope_path : absolute.lexically_normal().string();
  loadScopeDesign(path);  // refuses a file that is not a scope design now, not at the run
  scenario.scope_path = path;
  scenario.scope_replaced = true;
}

std::optional<double> useParameterFile(Scenario& scenario, const std::string& params_path) {
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(params_path, ec);
  scenario.params_path = ec ? params_path : absolute.lexically_normal().string();
  scenario.params_replaced = true;
  const std::optional<double> dropped = scenario.overrides.wall_friction;
  scenario.overrides.wall_friction.reset();
  scenario.overrides.colon_axial_rigidity_N.reset();
  return dropped;
}

}  // namespace colosim
