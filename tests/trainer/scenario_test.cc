// Scenarios: the shipped files load, SCENARIO resolves as a path or a name, inputs
// interpolate, and bad files are refused naming the file, key and line.
#include "trainer/scenario.h"

#include <cmath>

#include <gtest/gtest.h>

#include "fixture.h"
#include "session_fixture.h"
#include "trainer/json_position.h"
#include "trainer/strict_json.h"
#include "trainer/world_simulation.h"

namespace colosim {
namespace {

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos == std::string::npos) return text;
  return text.replace(pos, from.size(), to);
}

TEST(Scenario, ShippedScenariosLoadByName) {
  for (const std::string name : {"sigmoid_untwist", "sigmoid_push", "free_insertion"}) {
    SCOPED_TRACE(name);
    const Scenario s = findScenario(name);
    EXPECT_EQ(s.name, name);
    EXPECT_EQ(s.id, name);  // sessions name shipped scenarios by name
    EXPECT_EQ(s.dt_s, 0.001);
    EXPECT_GE(s.script.size(), 3u);
    EXPECT_NE(s.file_hash, 0u);
    EXPECT_EQ(findScenario(name + ".json").file, s.file);
  }
  const Scenario u = findScenario("sigmoid_untwist");
  EXPECT_NEAR(u.duration_s, 28.0, 2.0);  // the paper's benchmark, about 28 s
  EXPECT_EQ(u.start.kind, "scripted");
  EXPECT_EQ(u.scoring.start_s, u.start.until_s);
  // The untwist turns anticlockwise while withdrawing (more than a turn: its loop is a
  // reverse alpha loop); the push never turns.
  const Scenario p = findScenario("sigmoid_push");
  double min_rot_u = 1e9, max_abs_rot_p = 0;
  for (const Keyframe& k : u.script) min_rot_u = std::min(min_rot_u, k.input.rotation_rad);
  for (const Keyframe& k : p.script) max_abs_rot_p = std::max(max_abs_rot_p, std::abs(k.input.rotation_rad));
  EXPECT_LT(min_rot_u, -2 * 3.14159);
  EXPECT_EQ(max_abs_rot_p, 0.0);
  // The same start: identical scripts during the set-up.
  for (double t = 0; t <= u.start.until_s; t += 0.25) {
    EXPECT_EQ(scriptedInput(u.script, t).insertion_m, scriptedInput(p.script, t).insertion_m) << t;
    EXPECT_EQ(scriptedInput(u.script, t).rotation_rad, scriptedInput(p.script, t).rotation_rad) << t;
  }
  // free_insertion goes anus to caecum: 1.3-1.5 m of scope.
  const Scenario f = findScenario("free_insertion");
  EXPECT_GE(f.script.back().input.insertion_m, 1.3);
  EXPECT_LE(f.script.back().input.insertion_m, 1.5);
}

TEST(Scenario, ResolvesPathsAndRefusesUnknownNames) {
  test::TempDir dir;
  const std::string path = dir.write("mine.json", test::smallScenarioText("mine"));
  const Scenario s = findScenario(path);
  EXPECT_EQ(s.name, "mine");
  EXPECT_EQ(s.id.front(), '/');  // not shipped: named by its absolute path
  test::expectInputError([] { findScenario("no_such_scenario"); },
                         {"no_such_scenario", "sigmoid_untwist", "free_insertion"});
}

TEST(Scenario, InputsInterpolateLinearlyAndHoldAtTheEnds) {
  std::vector<Keyframe> script(2);
  script[0].t_s = 0;
  script[1].t_s = 2;
  script[1].input.insertion_m = 1.0;
  script[1].input.rotation_rad = -4.0;
  script[1].input.knob_updown_rad = 1.0;
  script[1].input.knob_leftright_rad = -0.5;
  const HandleInput mid = scriptedInput(script, 0.5);
  EXPECT_DOUBLE_EQ(mid.insertion_m, 0.25);
  EXPECT_DOUBLE_EQ(mid.rotation_rad, -1.0);
  EXPECT_DOUBLE_EQ(mid.knob_updown_rad, 0.25);
  EXPECT_DOUBLE_EQ(mid.knob_leftright_rad, -0.125);
  EXPECT_EQ(scriptedInput(script, 5.0).insertion_m, 1.0);
  EXPECT_EQ(scriptedInput(script, 0.0).insertion_m, 0.0);
}

constexpr const char* kRest = "\"start\": {\"kind\": \"rest\"}";
// smallScenarioText's start line with a colon shape of these points (a JSON list).
std::string shape(const std::string& points, const std::string& region = "sigmoid", const std::string& extra = "") {
  return "\"start\": {\"kind\": \"rest\", \"colon_shape\": {\"region\": \"" + region + "\", \"points_m\": " +
         points + extra + "}}";
}

TEST(Scenario, BadFilesNameFileKeyAndLine) {
  test::TempDir dir;
  const std::string good = test::smallScenarioText();
  struct Case {
    std::string from, to, fragment;
  };
  // Line numbers refer to smallScenarioText's layout.
  const std::vector<Case> cases = {
      {"\"version\": 1", "\"version\": 3", ":2: version: unsupported version 3"},
      {"\"dt_s\": 0.01", "\"dt_s\": 0.01, \"colour\": 1", ":5: colour: unknown key"},
      {"\"dt_s\": 0.01", "\"dt_s\": 0.5", ":5: dt_s"},
      {"\"kind\": \"rest\"", "\"kind\": \"asleep\"", ":6: start.kind"},
      {"{\"t_s\": 0.5,  \"insertion_m\": 0.0", "{\"t_s\": 0.5,  \"insertion_m\": 2.5", ":9: script[1].insertion_m"},
      {"\"knob_updown_rad\": 1.2", "\"knob_updown_rad\": 3.5", ":12: script[4].knob_updown_rad"},
      {"\"knob_leftright_rad\": -0.1}", "\"knob_leftright_rad\": 2.9}", ":10: script[2].knob_leftright_rad"},
      {"{\"t_s\": 1.2,", "{\"t_s\": 0.4,", ":11: script[3].t_s: keyframe times must increase"},
      {"{\"t_s\": 0.0,", "{\"t_s\": 0.1,", ":8: script[0].t_s"},
      {"\"rotation_rad\": 0.5, \"knob_updown_rad\": 0.2, \"knob_leftright_rad\": -0.1},\n    {\"t_s\": 1.2,",
       "\"rotation_rad\": 0.5, \"knob_updown_rad\": 0.2, \"knob_leftright_rad\": -0.1, \"speed\": 2},\n    {\"t_s\": 1.2,",
       ":10: script[2].speed: unknown key"},
      {"\"seed\": 7", "\"seed\": NaN", "line 5"},
      {"\"anatomy\": \"anatomy/adult.json\"", "\"anatomy\": \"anatomy/none.json\"", ":4: anatomy: no such file"},
      {"\"script\": [", "\"overrides\": {\"wall_friction\": 5},\n  \"script\": [", ":7: overrides.wall_friction"},
      {"\"script\": [", "\"overrides\": {\"colon_axial_rigidity_N\": 0},\n  \"script\": [",
       ":7: overrides.colon_axial_rigidity_N"},
      {"\"script\": [", "\"overrides\": {\"colon_axial_rigidity_N\": \"500\"},\n  \"script\": [",
       ":7: overrides.colon_axial_rigidity_N"},
      // The start state's colon shape (start.colon_shape): the list, each point, unknown keys.
      {kRest, shape("[[0,0,0.1],[0,0,0.2],[0,0,0.3]]"), ":6: start.colon_shape.points_m: expected a list of 4 to 1000"},
      {kRest, shape("[[0,0,0.1],[0,0,0.2],[0,\"x\",0.3],[0,0,0.4]]"),
       ":6: start.colon_shape.points_m[2]: coordinates must be finite numbers"},
      {kRest, shape("[[0,0,0.1],[0,0,0.2],[0,0,30],[0,0,0.4]]"), ":6: start.colon_shape.points_m[2]: coordinate out of range"},
      {kRest, shape("[[0,0,0.1],[0,0,0.2],[0,0,0.2],[0,0,0.4]]"), ":6: start.colon_shape.points_m[2]: closer than 0.1 mm"},
      {kRest, shape("[[0,0,0.1],[0,0,0.2],[0,0.1],[0,0,0.4]]"), ":6: start.colon_shape.points_m[2]: expected [x, y, z]"},
      {kRest, shape("[[0,0,0.1],[0,0,0.2],[0,0,0.3],[0,0,0.4]]", "sigmoid", ", \"twist\": 1"),
       ":6: start.colon_shape.twist: unknown key"},
      {kRest, shape("[[0,0,0.1],[0,0,0.2],[0,0,0.3],[0,0,0.4]]", ""), ":6: start.colon_shape.region: must not be empty"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.to);
    const std::string path = dir.write("bad.json", replaced(good, c.from, c.to));
    test::expectInputError([&] { loadScenario(path); }, {path, c.fragment});
  }
  // Cut off: a syntax error with its line.
  const std::string cut = dir.write("cut.json", good.substr(0, good.size() / 2));
  test::expectInputError([&] { loadScenario(cut); }, {cut, "invalid JSON", "line"});
}

// The colon's axial rigidity override replaces the parameter file's EA (and nothing else);
// a run with another parameter file (--params) drops it, as it drops the wall friction.
TEST(Scenario, ColonAxialRigidityOverrideSetsTheEA) {
  test::TempDir dir;
  const std::string text = replaced(test::smallScenarioText(), "\"script\": [",
                                    "\"overrides\": {\"colon_axial_rigidity_N\": 500},\n  \"script\": [");
  Scenario s = loadScenario(dir.write("ea.json", text));
  ASSERT_TRUE(s.overrides.colon_axial_rigidity_N.has_value());
  const Parameters file = loadParameters(s.params_path);
  const Parameters run = scenarioParameters(s);
  EXPECT_EQ(run.colon.tension_EA_N, 500.0);
  EXPECT_NEAR(file.colon.tension_EA_N, 28.9, 0.01);  // the paper's reading, left in the file
  EXPECT_EQ(run.colon.tension_EC_Ns, file.colon.tension_EC_Ns);
  EXPECT_EQ(run.contact.friction_coefficient, file.contact.friction_coefficient);
  useParameterFile(s, s.params_path);
  EXPECT_FALSE(s.overrides.colon_axial_rigidity_N.has_value());
  EXPECT_EQ(scenarioParameters(s).colon.tension_EA_N, file.colon.tension_EA_N);
}

// A colon shape that reads but does not fit the anatomy is refused when the simulation is
// built, naming the file and the key: a region the anatomy does not have, and points that
// do not start and end at the region's ends.
TEST(Scenario, ColonShapeMustFitTheAnatomy) {
  test::TempDir dir;
  const std::string good = test::smallScenarioText();
  const std::string pts = "[[0,0,0.1],[0,0.01,0.2],[0.02,0,0.3],[0,0,0.4]]";
  const std::string no_region = dir.write("no_region.json", replaced(good, kRest, shape(pts, "appendix")));
  const Scenario a = loadScenario(no_region);
  test::expectInputError([&] { WorldSimulation sim(a); }, {no_region + ":6: start.colon_shape.region: no region 'appendix'"});
  const std::string off_ends = dir.write("off_ends.json", replaced(good, kRest, shape(pts)));
  const Scenario b = loadScenario(off_ends);
  test::expectInputError([&] { WorldSimulation sim(b); },
                         {off_ends + ":6: start.colon_shape.points_m: must start within 1 cm of", "the sigmoid's ends"});
}

// smallScenarioText with an abdominal_pressure list (line 7) of these entries.
std::string withPressure(const std::string& list) {
  return replaced(test::smallScenarioText(), "\"script\": [", "\"abdominal_pressure\": " + list + ",\n  \"script\": [");
}
std::string pressure(const std::string& extra = "", const std::string& region = "sigmoid") {
  return "{\"region\": \"" + region + "\", \"from_s\": 0.2, \"to_s\": 2.0, \"stiffness_N_per_m2\": 1000, "
         "\"damping_Ns_per_m2\": 20" + extra + "}";
}

TEST(Scenario, AbdominalPressureIsReadStrictly) {
  test::TempDir dir;
  const Scenario ok = loadScenario(dir.write("ok.json", withPressure("[" + pressure(", \"ramp_s\": 0.5, \"note\": \"hand\"") +
                                                                      ", " + pressure("", "transverse") + "]")));
  ASSERT_EQ(ok.abdominal_pressure.size(), 2u);
  EXPECT_EQ(ok.abdominal_pressure[0].region, "sigmoid");
  EXPECT_EQ(ok.abdominal_pressure[0].from_s, 0.2);
  EXPECT_EQ(ok.abdominal_pressure[0].to_s, 2.0);
  EXPECT_EQ(ok.abdominal_pressure[0].ramp_s, 0.5);
  EXPECT_EQ(ok.abdominal_pressure[1].ramp_s, 1.0);  // the default ramp
  EXPECT_EQ(ok.abdominal_pressure[1].stiffness_N_per_m2, 1000.0);
  EXPECT_EQ(ok.abdominal_pressure[1].damping_Ns_per_m2, 20.0);
  EXPECT_TRUE(loadScenario(dir.write("none.json", test::smallScenarioText())).abdominal_pressure.empty());
  struct Case {
    std::string list, fragment;
  };
  const std::vector<Case> cases = {
      {"[]", ":7: abdominal_pressure: expected a list of 1 to 100"},
      {"{\"region\": \"sigmoid\"}", ":7: abdominal_pressure: expected a list of 1 to 100"},
      {"[3]", "abdominal_pressure[0]: expected a JSON object"},
      {"[" + pressure(", \"hand\": 1") + "]", ":7: abdominal_pressure[0].hand: unknown key"},
      {"[" + pressure("", "") + "]", ":7: abdominal_pressure[0].region: must not be empty"},
      {"[" + pressure() + ", " + replaced(pressure(), "1000", "1e6") + "]",
       ":7: abdominal_pressure[1].stiffness_N_per_m2: 1e+06 is out of range"},
      {"[" + replaced(pressure(), "20", "-1") + "]", ":7: abdominal_pressure[0].damping_Ns_per_m2:"},
      {"[" + replaced(pressure(), "\"to_s\": 2.0", "\"to_s\": 0.2") + "]", ":7: abdominal_pressure[0].to_s: must be after from_s"},
      {"[" + replaced(pressure(), "\"to_s\": 2.0", "\"to_s\": 9.0") + "]", ":7: abdominal_pressure[0].to_s: 9 is out of range"},
      {"[" + replaced(pressure(), "\"from_s\": 0.2", "\"from_s\": \"soon\"") + "]", ":7: abdominal_pressure[0].from_s: expected a number"},
      {"[" + replaced(pressure(), ", \"damping_Ns_per_m2\": 20", "") + "]", ":7: abdominal_pressure[0].damping_Ns_per_m2"},
      {"[" + pressure(", \"ramp_s\": 100") + "]", ":7: abdominal_pressure[0].ramp_s: 100 is out of range"},
      {"[" + replaced(pressure(), "1000", "NaN") + "]", "line 7"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.list);
    const std::string path = dir.write("bad.json", withPressure(c.list));
    test::expectInputError([&] { loadScenario(path); }, {path, c.fragment});
  }
  // A region the anatomy lacks: refused when the simulation is built, with file, line and key.
  const std::string no_region = dir.write("appendix.json", withPressure("[" + pressure() + ", " + pressure("", "appendix") + "]"));
  const Scenario a = loadScenario(no_region);
  test::expectInputError([&] { WorldSimulation sim(a); },
                         {no_region + ":7: abdominal_pressure[1].region: no region 'appendix' in the anatomy"});
}

// smallScenarioText with a patient_turns list (line 7) of these entries.
std::string withTurns(const std::string& list) {
  return replaced(test::smallScenarioText(), "\"script\": [", "\"patient_turns\": " + list + ",\n  \"script\": [");
}

TEST(Scenario, PatientTurnsAreReadStrictly) {
  test::TempDir dir;
  const Scenario ok = loadScenario(dir.write(
      "ok.json", withTurns(R"([{"at_s": 0.5, "position": "supine", "note": "onto the back"}, {"at_s": 1.5, "position": "right_lateral"}])")));
  ASSERT_EQ(ok.patient_turns.size(), 2u);
  EXPECT_EQ(ok.patient_turns[0].at_s, 0.5);
  EXPECT_EQ(ok.patient_turns[0].position, "supine");
  EXPECT_EQ(ok.patient_turns[1].position, "right_lateral");
  EXPECT_TRUE(loadScenario(dir.write("none.json", test::smallScenarioText())).patient_turns.empty());
  struct Case {
    std::string list, fragment;
  };
  const std::vector<Case> cases = {
      {"[]", ":7: patient_turns: expected a list of 1 to 100"},
      {R"([{"at_s": 0.5, "position": "standing"}])", ":7: patient_turns[0].position:"},
      {R"([{"at_s": 0.5}])", ":7: patient_turns[0].position"},
      {R"([{"at_s": 9.0, "position": "supine"}])", ":7: patient_turns[0].at_s: 9 is out of range"},
      {R"([{"at_s": 1.0, "position": "supine"}, {"at_s": 1.0, "position": "prone"}])",
       ":7: patient_turns[1].at_s: must be after the previous turn's"},
      {R"([{"at_s": 0.5, "position": "supine", "speed": 2}])", ":7: patient_turns[0].speed: unknown key"},
      {R"([{"at_s": NaN, "position": "supine"}])", "line 7"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.list);
    const std::string path = dir.write("bad.json", withTurns(c.list));
    test::expectInputError([&] { loadScenario(path); }, {path, c.fragment});
  }
}

// The pressure changes the run only while it is on: the colon settling under gravity with
// the scope out, the pressed sigmoid (held from 0.2 s where it then lies) sags a few
// millimetres where the free one sags centimetres; a run with it replays bit-identically
// (it comes from the scenario file).
TEST(Scenario, AbdominalPressureHoldsTheRegionAndIsDeterministic) {
  test::TempDir dir;
  const Scenario free_sc = loadScenario(dir.write("free.json", test::smallScenarioText()));
  // Pressed from 0.2 s to the end (2.5 s), ramped in over 0.2 s.
  const std::string held = replaced(pressure(", \"ramp_s\": 0.2"), "\"to_s\": 2.0", "\"to_s\": 2.5");
  const Scenario pressed = loadScenario(dir.write("pressed.json", withPressure("[" + held + "]")));
  auto run = [](const Scenario& sc, double until_s, double* sag_m) {
    WorldSimulation sim(sc);
    const ColonModel& m = sim.model().colon;
    std::vector<int> sigmoid;  // the sigmoid's inner control points
    for (int j = 1; j + 1 < m.n; ++j)
      if (m.region_names[m.segment_region[j - 1]] == "sigmoid" && m.region_names[m.segment_region[j]] == "sigmoid")
        sigmoid.push_back(j);
    const long steps = std::lround(until_s / sc.dt_s);
    std::vector<Vec3> at_anchor;
    for (long k = 0; k < steps; ++k) {
      if (k == std::lround(0.2 / sc.dt_s))
        for (int j : sigmoid) at_anchor.push_back(sim.state().colon.q.col(j));
      sim.step(HandleInput());  // the scope stays out: only gravity moves the colon
    }
    // Mean displacement of the sigmoid's control points since 0.2 s.
    double d = 0;
    for (size_t i = 0; i < sigmoid.size() && i < at_anchor.size(); ++i)
      d += (sim.state().colon.q.col(sigmoid[i]) - at_anchor[i]).norm() / sigmoid.size();
    *sag_m = d;
    return sim.stateHash();
  };
  double d_free = 0, d_pressed = 0, d_again = 0, d_before = 0, d_free_before = 0;
  const uint64_t h_free = run(free_sc, 2.4, &d_free);
  const uint64_t h_pressed = run(pressed, 2.4, &d_pressed);
  EXPECT_NE(h_free, h_pressed);
  EXPECT_EQ(run(pressed, 2.4, &d_again), h_pressed);
  EXPECT_GT(d_free, 0.002) << d_free;  // the free sigmoid falls millimetres in 2.2 s
  EXPECT_LT(d_pressed, 0.2 * d_free) << d_pressed << " " << d_free;
  // Before from_s (0.2 s) the runs are the same.
  EXPECT_EQ(run(pressed, 0.2, &d_before), run(free_sc, 0.2, &d_free_before));
}

TEST(Scenario, KeyPathsMapToLines) {
  const std::string text = "{\n  \"a\": 1,\n  \"b\": {\"c\": [\n    10,\n    {\"d\": 2}\n  ]}\n}";
  EXPECT_EQ(lineOfKeyPath(text, "a"), 2);
  EXPECT_EQ(lineOfKeyPath(text, "b.c"), 3);
  EXPECT_EQ(lineOfKeyPath(text, "b.c[0]"), 4);
  EXPECT_EQ(lineOfKeyPath(text, "b.c[1].d"), 5);
  EXPECT_EQ(lineOfKeyPath(text, "b.c[1].missing"), 5);  // its nearest existing ancestor
  EXPECT_EQ(lineOfKeyPath(text, "zz"), 0);
}

}  // namespace
}  // namespace colosim
