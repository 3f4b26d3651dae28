#include "trainer/scope_design.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/input_error.h"
#include "fixture.h"
#include "trainer/assets.h"
#include "trainer/scenario.h"

namespace colosim {
namespace {

std::string standardWith(const std::string& from, const std::string& to) {
  std::string text = test::readFile(test::asset("scopes/standard.json"));
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

void expectError(const std::string& text, std::initializer_list<std::string> fragments) {
  try {
    parseScopeDesign(text, "bad.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    for (const std::string& f : fragments)
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what() << "\n  lacks: " << f;
  }
}

// The standard design is today's scope: applied to the default parameters it changes
// nothing, so scenarios that name no design run as before (the golden hashes pin it).
TEST(ScopeDesign, TheStandardDesignIsTheDefaultParametersScope) {
  const Parameters params = loadParameters(test::asset("params/default.json"));
  const ScopeDesign d = loadScopeDesign(test::asset("scopes/standard.json"));
  ScopeParams applied = params.scope;
  applyScopeDesign(d, applied);
  EXPECT_EQ(applied.working_length_m, params.scope.working_length_m);
  EXPECT_EQ(applied.outer_diameter_m, params.scope.outer_diameter_m);
  EXPECT_EQ(applied.mass_per_length_kg_per_m, params.scope.mass_per_length_kg_per_m);
  EXPECT_EQ(applied.bending_stiffness_Nm2, params.scope.bending_stiffness_Nm2);
  EXPECT_EQ(applied.torsional_stiffness_Nm2, params.scope.torsional_stiffness_Nm2);
  EXPECT_EQ(applied.bending_section_length_m, params.scope.bending_section_length_m);
  EXPECT_EQ(d.sheath_friction, params.contact.friction_coefficient);
  EXPECT_EQ(d.knob_updown_max_rad, kKnobUpDownMax_rad);
  EXPECT_EQ(d.knob_leftright_max_rad, kKnobLeftRightMax_rad);
  const ScopeModel a = buildScopeModel(params.scope, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitY(), Vec3::Zero());
  const ScopeModel b = buildScopeModel(applied, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitY(), Vec3::Zero());
  ASSERT_EQ(a.joint_stiffness_Nm_per_rad.size(), b.joint_stiffness_Nm_per_rad.size());
  for (size_t k = 0; k < a.joint_stiffness_Nm_per_rad.size(); ++k)
    EXPECT_EQ(a.joint_stiffness_Nm_per_rad[k], b.joint_stiffness_Nm_per_rad[k]) << k;
}

// Each joint takes the section its arclength from the tip lies in.
TEST(ScopeDesign, JointsTakeTheirSectionsStiffness) {
  ScopeParams p;
  p.working_length_m = 0.3;
  p.segment_length_m = 0.015;  // 20 segments, joints at 0.015 .. 0.285 m from the tip
  p.stiffness_profile = {{0.1, 0.01, 0.2}, {0.2, 0.05, 0.6}, {0.3, 0.02, 0.3}};
  const ScopeModel m = buildScopeModel(p, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitY(), Vec3::Zero());
  ASSERT_EQ(m.joint_stiffness_Nm_per_rad.size(), 19u);
  for (int k = 0; k < 19; ++k) {
    const double s_m = (k + 1) * 0.015;
    const StiffnessSection& sec = s_m < 0.1 - 1e-12 ? p.stiffness_profile[0]
                                  : s_m < 0.2 - 1e-12 ? p.stiffness_profile[1]
                                                      : p.stiffness_profile[2];
    EXPECT_DOUBLE_EQ(m.joint_stiffness_Nm_per_rad[k].x(), sec.bending_stiffness_Nm2 / 0.015) << k;
    EXPECT_DOUBLE_EQ(m.joint_stiffness_Nm_per_rad[k].y(), sec.bending_stiffness_Nm2 / 0.015) << k;
    EXPECT_DOUBLE_EQ(m.joint_stiffness_Nm_per_rad[k].z(), sec.torsional_stiffness_Nm2 / 0.015) << k;
  }
  p.stiffness_profile = {{0.2, 0.01, 0.2}, {0.1, 0.05, 0.6}};
  EXPECT_THROW(buildScopeModel(p, Vec3::Zero(), Vec3::UnitZ(), Vec3::UnitY(), Vec3::Zero()), std::invalid_argument);
}

TEST(ScopeDesign, BadFilesAreRefusedNamingKeyAndLine) {
  expectError(standardWith("\"colosim-scope\"", "\"colosim-params\""), {"bad.json", "format"});
  expectError(standardWith("\"to_m\": 1.6", "\"to_m\": 1.5"), {"stiffness_profile.sections", "working length"});
  expectError(standardWith("\"bending_stiffness_Nm2\": 0.03", "\"bending_stiffness_Nm2\": -0.03"),
              {"bad.json:26:", "stiffness_profile.sections[0].bending_stiffness_Nm2"});
  expectError(standardWith("\"sheath_friction\": {", "\"sheath_frictoin\": {"), {"sheath_friction", "missing"});
  expectError(standardWith("\"value\": 3.141592653589793", "\"value\": 4.0"), {"knob_updown_max"});
  expectError(standardWith("\"version\": 1", "\"version\": 1, \"colour\": \"black\""), {"colour"});
  expectError(standardWith("\"value\": 0.0125", "\"value\": NaN"), {"bad.json"});
}

// The active and variable-stiffness designs (issue 20): the optional blocks read into the
// scope's parameters, strictly.
TEST(ScopeDesign, ActiveAndVariableStiffnessBlocks) {
  const ScopeDesign ftl = loadScopeDesign(test::asset("scopes/follow_the_leader.json"));
  EXPECT_TRUE(ftl.active.enabled);
  EXPECT_EQ(ftl.active.strategy, ActiveStrategy::kFollowTheLeader);
  EXPECT_EQ(ftl.active.joint_torque_limit_Nm, 0.5);
  EXPECT_EQ(ftl.active.time_constant_s, 0.2);
  EXPECT_EQ(ftl.active.actuated_length_m, 0.8);
  const ScopeDesign cm = loadScopeDesign(test::asset("scopes/contact_minimising.json"));
  EXPECT_EQ(cm.active.strategy, ActiveStrategy::kContactMinimising);
  const ScopeDesign vs = loadScopeDesign(test::asset("scopes/variable_stiffness.json"));
  EXPECT_FALSE(vs.active.enabled);
  EXPECT_EQ(vs.variable_stiffness.levels, (std::vector<double>{1.0, 1.5, 2.0, 2.5}));
  EXPECT_EQ(vs.variable_stiffness.from_m, 0.3);
  EXPECT_EQ(vs.variable_stiffness.default_level, 0);
  ScopeParams p;
  applyScopeDesign(vs, p);
  EXPECT_EQ(p.variable_stiffness.levels.size(), 4u);
  const ScopeDesign hf = loadScopeDesign(test::asset("scopes/hyper_flaccid.json"));
  ASSERT_EQ(hf.stiffness_profile.size(), 3u);
  EXPECT_EQ(hf.stiffness_profile[1].bending_stiffness_Nm2, 0.005);
  EXPECT_TRUE(loadScopeDesign(test::asset("scopes/standard.json")).variable_stiffness.levels.empty());

  const std::string ftl_text = test::readFile(test::asset("scopes/follow_the_leader.json"));
  auto with = [&](const std::string& text, const std::string& from, const std::string& to) {
    std::string t = text;
    const auto pos = t.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return t.replace(pos, from.size(), to);
  };
  expectError(with(ftl_text, "\"strategy\": \"follow_the_leader\"", "\"strategy\": \"follow_the_lead\""),
              {"bad.json:", "active.strategy"});
  expectError(with(ftl_text, "\"time_constant_s\": 0.2", "\"time_constant_s\": 0"), {"active.time_constant_s"});
  expectError(with(ftl_text, "\"actuated_length_m\": 0.8", "\"actuated_length_m\": 2.5"), {"active.actuated_length_m", "working length"});
  expectError(with(ftl_text, "\"strategy\"", "\"strategie\": 1, \"strategy\""), {"strategie"});
  const std::string vs_text = test::readFile(test::asset("scopes/variable_stiffness.json"));
  expectError(with(vs_text, "\"default_level\": 0", "\"default_level\": 4"), {"variable_stiffness.default_level"});
  expectError(with(vs_text, "\"from_m\": 0.3", "\"from_m\": 1.7"), {"variable_stiffness.to_m"});
  expectError(with(vs_text, "1.5,", "-1.5,"), {"variable_stiffness.levels"});
}

// A design given for the run is used (its sheath friction too) and sessions record it.
TEST(ScopeDesign, AScenarioRunsWithTheDesignItIsGiven) {
  Scenario sc = findScenario("sigmoid_push");
  EXPECT_EQ(sc.scope_path, assetPath(kDefaultScopeDesign));
  EXPECT_FALSE(sc.scope_replaced);
  const std::string text = standardWith("\"value\": 0.1,", "\"value\": 0.25,");
  const std::string path = ::testing::TempDir() + "/slippery_scope.json";
  std::ofstream(path) << text;
  useScopeDesign(sc, path);
  EXPECT_TRUE(sc.scope_replaced);
  EXPECT_EQ(scenarioParameters(sc).contact.friction_coefficient, 0.25);
  EXPECT_THROW(useScopeDesign(sc, test::asset("params/default.json")), InputError);
}

}  // namespace
}  // namespace colosim
