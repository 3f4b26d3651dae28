// `colosim identify --law-out` on a recorded insertion writes a parameter file with which
// `colosim run SCENARIO --params FILE` simulates the model the identification fitted: wall
// friction, colon bending, lifter stiffening and the tension-law effects (colon.tension_law).
#include <algorithm>
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/input_error.h"
#include "fixture.h"
#include "identify/insertion/identify.h"
#include "trainer/session_fixture.h"
#include "trainer/replay.h"
#include "trainer/world_simulation.h"

namespace colosim {
namespace {

// The shipped default parameters at the identification's search resolution (3 cm), so that
// the runs below are short.
std::string coarseDefaults(const test::TempDir& dir) {
  nlohmann::json j = nlohmann::json::parse(test::readFile(test::asset("params/default.json")));
  j["colon"]["control_point_spacing"]["value"] = 0.03;
  j["scope"]["segment_length"]["value"] = 0.03;
  return dir.write("coarse.json", j.dump(2));
}

// A 1.5 s scenario on those parameters: the colon settles for 0.3 s, the scope starts
// threaded to 15 cm, is pushed to 27 cm turning and steering, held, pulled back 5 cm. It
// carries a wall_friction override, as free_insertion does, which --params must not apply
// (or the overrides given, on line 6 of the file).
Scenario shortScenario(const test::TempDir& dir, const std::string& params,
                       const std::string& overrides = R"({"wall_friction": 0.1})") {
  const std::string text = R"({
    "format": "colosim-scenario", "version": 1, "name": "law_out_round_trip",
    "description": "test", "anatomy": "anatomy/adult.json", "params": ")" + params + R"(",
    "dt_s": 0.001, "duration_s": 1.5, "seed": 1,
    "start": {"kind": "settled", "settle_s": 0.3},
    "overrides": )" + overrides + R"(,
    "script": [
      {"t_s": 0.0, "insertion_m": 0.15, "rotation_rad": 0.0, "knob_updown_rad": 0.0, "knob_leftright_rad": 0.0},
      {"t_s": 0.8, "insertion_m": 0.27, "rotation_rad": 0.3, "knob_updown_rad": 0.3, "knob_leftright_rad": 0.0},
      {"t_s": 1.0, "insertion_m": 0.27, "rotation_rad": 0.3, "knob_updown_rad": 0.3, "knob_leftright_rad": 0.0},
      {"t_s": 1.5, "insertion_m": 0.22, "rotation_rad": 0.0, "knob_updown_rad": 0.0, "knob_leftright_rad": 0.0}]})";
  return loadScenario(dir.write("scenario.json", text));
}

// The base parameters with a fitted tension law (a set ratio of 0.2), written to NAME.
std::string writeWithTensionLaw(const test::TempDir& dir, const std::string& base, const std::string& name) {
  InsertionFit fit;
  fit.params.set_ratio = 0.2;
  const std::string path = dir.file(name);
  writeOrganParameters(path, base, fit, "test");
  return path;
}

// The handle force of every step of the scenario's scripted run [N].
std::vector<double> handleForces(const Scenario& sc, WorldSimulation& sim) {
  std::vector<double> f;
  RunHooks hooks;
  hooks.on_step = [&](const Telemetry& t) { f.push_back(t.handle_force_N); };
  runScenario(sc, sim, nullptr, hooks);
  return f;
}

double maxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double m = 0;
  for (size_t k = 0; k < std::min(a.size(), b.size()); ++k) m = std::max(m, std::abs(a[k] - b[k]));
  return m;
}

TEST(OrganLawOut, RunWithTheWrittenParametersSimulatesTheFittedModel) {
  test::TempDir dir;
  const std::string base = coarseDefaults(dir);
  const Scenario sc = shortScenario(dir, base);
  // A fitted model with every extension on (hand-written: the identification's InsertionFit).
  InsertionFit fit;
  fit.params.friction = 0.25;
  fit.params.bending_EI_Nm2 = 0.02;
  fit.params.stiffening_per_m2 = 5000;
  fit.params.fung_b = 5;
  fit.params.relax_g1 = 0.4;
  fit.params.soften_d_inf = 0.3;
  fit.params.set_ratio = 0.2;
  const std::string out = dir.file("identified.json");
  writeOrganParameters(out, base, fit, "law_out_test");

  // The file carries the tension law with the fitted values and the base's EA and EC.
  const Parameters written = loadParameters(out);
  ASSERT_TRUE(written.tension_law.has_value());
  EXPECT_EQ(written.tension_law->effects(), tensionEffectNames());
  EXPECT_EQ(written.tension_law->fung_b, 5);
  EXPECT_EQ(written.tension_law->relax_g1, 0.4);
  EXPECT_EQ(written.tension_law->relax_tau1_s, kRelaxTau_s);
  EXPECT_EQ(written.tension_law->soften_d_inf, 0.3);
  EXPECT_EQ(written.tension_law->soften_a_c, kSoftenAc);
  EXPECT_EQ(written.tension_law->set_ratio, 0.2);
  EXPECT_EQ(written.tension_law->ea_N, loadParameters(base).colon.tension_EA_N);

  // The identification's model: the scenario's parameters (without its friction override,
  // as makeReplaySetup) with the fitted extensions (organParameters, what replayInsertion runs).
  const Parameters replayed = makeReplaySetup(sc).params;
  WorldSimulation identified(sc, organParameters(replayed, fit.params));
  const std::vector<double> f_identified = handleForces(sc, identified);
  // `colosim run SCENARIO --params FILE`: the file replaces the scenario's and its override.
  Scenario with_file = sc;
  const std::optional<double> dropped = useParameterFile(with_file, out);
  ASSERT_TRUE(dropped.has_value());
  EXPECT_EQ(*dropped, 0.1);
  WorldSimulation run(with_file);
  EXPECT_NE(run.model().colon.tension_law->internalSize(), 0);
  const std::vector<double> f_run = handleForces(with_file, run);
  ASSERT_EQ(f_run.size(), 1500u);
  EXPECT_LE(maxDifference(f_run, f_identified), 1e-9);
  EXPECT_EQ(run.stateHash(), identified.stateHash());

  // The comparison can fail: the paper's model, and the fitted model without its tension
  // law, give other forces.
  WorldSimulation paper(sc, organParameters(replayed, OrganParams{}));
  OrganParams no_law = fit.params;
  no_law.fung_b = no_law.relax_g1 = no_law.soften_d_inf = no_law.set_ratio = 0;
  WorldSimulation without_law(sc, organParameters(replayed, no_law));
  const double d_paper = maxDifference(f_run, handleForces(sc, paper));
  const double d_law = maxDifference(f_run, handleForces(sc, without_law));
  std::printf("largest handle-force difference of the run from: the fitted model %.3g N, the paper's %.3f N, the "
              "fitted model without its tension law %.3f N\n",
              maxDifference(f_run, f_identified), d_paper, d_law);
  EXPECT_GT(d_paper, 0.05);
  EXPECT_GT(d_law, 0.01);
}

TEST(OrganLawOut, AFitWithoutTensionEffectsRemovesTheBaseFilesLaw) {
  test::TempDir dir;
  const std::string base = coarseDefaults(dir);
  const std::string first = writeWithTensionLaw(dir, base, "first.json");
  ASSERT_TRUE(loadParameters(first).tension_law.has_value());
  InsertionFit friction_only;
  friction_only.params.friction = 0.3;
  const std::string second = dir.file("second.json");
  writeOrganParameters(second, first, friction_only, "test");
  const Parameters p = loadParameters(second);
  EXPECT_FALSE(p.tension_law.has_value());
  EXPECT_EQ(p.contact.friction_coefficient, 0.3);
}

// A scenario that overrides the colon's EA (as free_insertion does) of a parameter file
// carrying a tension law would contradict the law's EA: refused, naming the scenario's line.
TEST(OrganLawOut, AnEAOverrideOfAFileWithATensionLawIsAnError) {
  test::TempDir dir;
  const std::string base = coarseDefaults(dir);
  const std::string with_law = writeWithTensionLaw(dir, base, "with_law.json");
  const Scenario sc = shortScenario(dir, with_law, R"({"colon_axial_rigidity_N": 500})");
  test::expectInputError([&] { scenarioParameters(sc); },
                         {sc.file + ":6: overrides.colon_axial_rigidity_N", "tension law"});
  // Without the law the override applies.
  Scenario plain = sc;
  plain.params_path = base;
  EXPECT_EQ(scenarioParameters(plain).colon.tension_EA_N, 500.0);
}

TEST(OrganLawOut, ALawWhoseStiffnessDisagreesWithTheParametersIsAnError) {
  test::TempDir dir;
  const std::string base = coarseDefaults(dir);
  InsertionFit fit;
  fit.params.fung_b = 4;
  const std::string out = dir.file("identified.json");
  writeOrganParameters(out, base, fit, "test");
  nlohmann::json j = nlohmann::json::parse(test::readFile(out));
  j["colon"]["tension_law"]["params"]["EA_N"]["value"] = 30.0;
  const std::string bad = dir.write("bad.json", j.dump(2));
  try {
    loadParameters(bad);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("colon.tension_law.params.EA_N"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace colosim
