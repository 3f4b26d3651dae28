#include "trainer/assets.h"

#include <gtest/gtest.h>

#include "fixture.h"
#include "trainer/strict_json.h"

namespace colosim {
namespace {

// Expects an InputError whose message contains every fragment.
template <typename F>
void expectInputError(F&& f, std::initializer_list<std::string> fragments) {
  try {
    f();
    FAIL() << "no error";
  } catch (const InputError& e) {
    for (const std::string& frag : fragments)
      EXPECT_NE(std::string(e.what()).find(frag), std::string::npos) << e.what() << "\n  lacks: " << frag;
  }
}

// The default parameter file with one textual replacement.
std::string paramsWith(const std::string& from, const std::string& to) {
  std::string text = test::readFile(test::asset("params/default.json"));
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

std::string anatomyWith(const std::string& from, const std::string& to) {
  std::string text = test::readFile(test::asset("anatomy/adult.json"));
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

TEST(Assets, ShippedFilesLoad) {
  const Parameters p = loadParameters(test::asset("params/default.json"));
  EXPECT_NEAR(p.colon.tension_EA_N, 892 * 0.18 * 0.18, 1e-9);
  EXPECT_EQ(p.colon.mass_per_length_kg_per_m, 0.4);
  EXPECT_EQ(p.colon.mesentery.size(), 3u);  // pelvic, attached, free
  EXPECT_NE(p.hash, 0u);
  const Anatomy a = loadAnatomy(test::asset("anatomy/adult.json"));
  EXPECT_EQ(a.regions.front().name, "rectum");
  EXPECT_EQ(a.regions.back().name, "caecum");
}

TEST(Assets, UnknownKeyIsNamed) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", paramsWith("\"colon\": {", "\"colon\": {\"colour\": 1,"));
  expectInputError([&] { loadParameters(f); }, {f, "colon.colour", "unknown key"});
  // A misspelt key is reported as missing, with the misspelling shown beside it.
  const std::string g = dir.write("q.json", paramsWith("\"mass_per_length\"", "\"mass_per_lenght\""));
  expectInputError([&] { loadParameters(g); }, {g, "colon.mass_per_length: missing key", "mass_per_lenght"});
}

TEST(Assets, MissingKeyIsNamed) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", paramsWith("\"tension_viscosity\"", "\"note_tension_viscosity\""));
  expectInputError([&] { loadParameters(f); }, {f, "colon.tension_viscosity", "missing key"});
}

TEST(Assets, WrongUnitIsRefused) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", paramsWith("\"unit\": \"kg/m\"", "\"unit\": \"g/m\""));
  expectInputError([&] { loadParameters(f); }, {f, "colon.mass_per_length.unit", "kg/m", "g/m"});
}

TEST(Assets, NegativeMassIsRefused) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", paramsWith("\"value\": 0.4", "\"value\": -0.4"));
  expectInputError([&] { loadParameters(f); }, {f, "colon.mass_per_length.value", "out of range"});
}

TEST(Assets, NegativeLengthIsRefused) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", paramsWith("\"value\": 0.015", "\"value\": -0.015"));
  expectInputError([&] { loadParameters(f); }, {f, "colon.control_point_spacing.value", "out of range"});
  const std::string a = dir.write("a.json", anatomyWith("\"radius_m\": [0.02, 0.022]", "\"radius_m\": [-0.02, 0.022]"));
  expectInputError([&] { loadAnatomy(a); }, {a, "regions[0].radius_m[0]", "out of range"});
}

TEST(Assets, CompressionStiffnessFractionIsOptionalAndWithinZeroToOne) {
  test::TempDir dir;
  const std::string key = "\"compression_stiffness_fraction\": {\n        \"value\": 1.0";
  const std::string soft = dir.write("soft.json", paramsWith(key, "\"compression_stiffness_fraction\": {\"value\": 0.2"));
  EXPECT_EQ(loadParameters(soft).colon.compression_stiffness_fraction, 0.2);
  const std::string f = dir.write("p.json", paramsWith(key, "\"compression_stiffness_fraction\": {\"value\": 1.5"));
  expectInputError([&] { loadParameters(f); }, {f, "colon.compression_stiffness_fraction.value", "out of range"});
  // Left out (parameter files written before it): the paper's element.
  std::string text = test::readFile(test::asset("params/default.json"));
  const auto a = text.find(",\n    \"compression_stiffness_fraction\"");
  const auto b = text.find("}", text.find("\"note\"", a)) + 1;
  ASSERT_NE(a, std::string::npos);
  const std::string old = dir.write("old.json", text.erase(a, b - a));
  EXPECT_EQ(loadParameters(old).colon.compression_stiffness_fraction, 1.0);
}

TEST(Assets, HaustralFoldsAreOptionalAndWithinRange) {
  test::TempDir dir;
  EXPECT_EQ(loadParameters(test::asset("params/default.json")).colon.haustral_fold_depth, 0.0);  // absent: a smooth tube
  const std::string key = "\"colon\": {";
  const std::string ok = dir.write("ok.json", paramsWith(key, "\"colon\": {\"haustral_fold_depth\": {\"value\": 0.25, \"unit\": \"1\", \"source\": \"test\"}, "
                                                                "\"haustral_fold_period\": {\"value\": 0.04, \"unit\": \"m\", \"source\": \"test\"},"));
  EXPECT_EQ(loadParameters(ok).colon.haustral_fold_depth, 0.25);
  EXPECT_EQ(loadParameters(ok).colon.haustral_fold_period_m, 0.04);
  const std::string f = dir.write("p.json", paramsWith(key, "\"colon\": {\"haustral_fold_depth\": {\"value\": 0.95, \"unit\": \"1\", \"source\": \"test\"},"));
  expectInputError([&] { loadParameters(f); }, {f, "colon.haustral_fold_depth.value", "out of range"});
  const std::string g = dir.write("g.json", paramsWith(key, "\"colon\": {\"haustral_fold_period\": {\"value\": 0, \"unit\": \"m\", \"source\": \"test\"},"));
  expectInputError([&] { loadParameters(g); }, {g, "colon.haustral_fold_period.value", "out of range"});
}

// contact.wall_reference_slice_length is optional (the shipped files leave it out: 1.5 cm,
// their segment length) and within [0, 0.1] m.
TEST(Assets, WallReferenceSliceLengthIsOptionalAndInRange) {
  test::TempDir dir;
  EXPECT_EQ(loadParameters(test::asset("params/default.json")).contact.wall_reference_slice_m, 0.015);
  const std::string key = "\"query_margin\": {";
  auto with = [&](const std::string& name, const std::string& value) {
    return dir.write(name, paramsWith(key, "\"wall_reference_slice_length\": {\"value\": " + value +
                                               ", \"unit\": \"m\", \"source\": \"test\"},\n    " + key));
  };
  EXPECT_EQ(loadParameters(with("half.json", "0.0075")).contact.wall_reference_slice_m, 0.0075);
  const std::string bad = with("bad.json", "-0.01");
  expectInputError([&] { loadParameters(bad); }, {bad, "contact.wall_reference_slice_length.value", "out of range"});
}

// contact.wall_reference_points_per_slice is optional (left out: 6, the shipped count), a
// whole number within [0, 32].
TEST(Assets, WallReferencePointsPerSliceIsOptionalWholeAndInRange) {
  test::TempDir dir;
  EXPECT_EQ(loadParameters(test::asset("params/default.json")).contact.wall_reference_points_per_slice, 6);
  const std::string key = "\"query_margin\": {";
  auto with = [&](const std::string& name, const std::string& value) {
    return dir.write(name, paramsWith(key, "\"wall_reference_points_per_slice\": {\"value\": " + value +
                                               ", \"unit\": \"1\", \"source\": \"test\"},\n    " + key));
  };
  EXPECT_EQ(loadParameters(with("eight.json", "8")).contact.wall_reference_points_per_slice, 8);
  EXPECT_EQ(loadParameters(with("none.json", "0")).contact.wall_reference_points_per_slice, 0);
  const std::string bad = with("bad.json", "40");
  expectInputError([&] { loadParameters(bad); }, {bad, "contact.wall_reference_points_per_slice.value", "out of range"});
  const std::string half = with("half.json", "6.5");
  expectInputError([&] { loadParameters(half); }, {half, "wall_reference_points_per_slice", "whole number"});
}

// contact.coupling_predictor (0 or 1) and contact.coupling_sweeps (a whole number 0..8) are
// optional; the shipped patient leaves both out (the step as before session 40).
TEST(Assets, ContactCouplingKeysAreOptionalAndChecked) {
  test::TempDir dir;
  const Parameters shipped = loadParameters(test::asset("params/default.json"));
  EXPECT_TRUE(shipped.contact.coupling_predictor);  // on since session 43
  EXPECT_EQ(shipped.contact.coupling_sweeps, 0);
  const std::string predictor = "\"coupling_predictor\": {\n        \"value\": 1";
  auto predicting = [&](const std::string& name, const std::string& value) {
    return dir.write(name, paramsWith(predictor, "\"coupling_predictor\": {\n        \"value\": " + value));
  };
  EXPECT_FALSE(loadParameters(predicting("off.json", "0")).contact.coupling_predictor);
  const std::string half_on = predicting("half_on.json", "0.5");
  expectInputError([&] { loadParameters(half_on); }, {half_on, "coupling_predictor", "0 or 1"});
  const std::string two = predicting("two.json", "2");
  expectInputError([&] { loadParameters(two); }, {two, "contact.coupling_predictor.value", "out of range"});
  // Left out (parameter files written before it): the lag.
  std::string text = test::readFile(test::asset("params/default.json"));
  const auto a = text.find(",\n    \"coupling_predictor\"");
  ASSERT_NE(a, std::string::npos);
  const auto b = text.find("}", text.find("\"source\"", a)) + 1;
  EXPECT_FALSE(loadParameters(dir.write("old.json", text.erase(a, b - a))).contact.coupling_predictor);
  const std::string key = "\"query_margin\": {";
  auto with = [&](const std::string& name, const std::string& entry, const std::string& value) {
    return dir.write(name, paramsWith(key, "\"" + entry + "\": {\"value\": " + value +
                                               ", \"unit\": \"1\", \"source\": \"test\"},\n    " + key));
  };
  EXPECT_EQ(loadParameters(with("three.json", "coupling_sweeps", "3")).contact.coupling_sweeps, 3);
  const std::string many = with("many.json", "coupling_sweeps", "9");
  expectInputError([&] { loadParameters(many); }, {many, "contact.coupling_sweeps.value", "out of range"});
  const std::string frac = with("frac.json", "coupling_sweeps", "1.5");
  expectInputError([&] { loadParameters(frac); }, {frac, "coupling_sweeps", "whole number"});
}

TEST(Assets, NaNAndInfinityAreRefused) {
  test::TempDir dir;
  const std::string nan = dir.write("nan.json", paramsWith("\"value\": 0.4", "\"value\": NaN"));
  expectInputError([&] { loadParameters(nan); }, {nan, "invalid JSON", "line"});
  const std::string inf = dir.write("inf.json", paramsWith("\"value\": 0.4", "\"value\": 1e999"));
  expectInputError([&] { loadParameters(inf); }, {inf, "invalid JSON", "1e999"});
}

TEST(Assets, SyntaxErrorsGiveTheLine) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", "{\n  \"format\": \"colosim-params\",\n  \"version\": 1,,\n}");
  expectInputError([&] { loadParameters(f); }, {f, "line 3"});
}

TEST(Assets, DuplicateKeysAreRefused) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", paramsWith("\"version\": 1,", "\"version\": 1, \"version\": 1,"));
  expectInputError([&] { loadParameters(f); }, {f, "duplicate key 'version'"});
}

TEST(Assets, WrongFormatOrVersionIsRefused) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", paramsWith("\"version\": 1", "\"version\": 2"));
  expectInputError([&] { loadParameters(f); }, {f, "version", "unsupported"});
  expectInputError([&] { loadParameters(test::asset("anatomy/adult.json")); }, {"format", "colosim-params"});
}

TEST(Assets, UnknownPatientPositionIsRefused) {
  test::TempDir dir;
  const std::string f = dir.write("p.json", paramsWith("\"left_lateral\"", "\"standing\""));
  expectInputError([&] { loadParameters(f); }, {f, "environment.patient_position.value", "standing"});
}

TEST(Assets, AnatomyInCentimetresIsRefused) {
  test::TempDir dir;
  const std::string f = dir.write("a.json", anatomyWith("[0, 0.025, 0.04]", "[0, 2.5, 4.0]"));
  expectInputError([&] { loadAnatomy(f); }, {f, "regions[0].points_m[1]", "wrong unit"});
}

TEST(Assets, AnatomyWithAnUnknownMesenteryClassIsRefused) {
  test::TempDir dir;
  const std::string f = dir.write("a.json", anatomyWith("\"mesentery\": \"free\"", "\"mesentery\": \"floppy\""));
  const Parameters p = loadParameters(test::asset("params/default.json"));
  expectInputError([&] { loadColonModel(f, p); }, {f, "floppy"});
}

TEST(Assets, MissingFileIsNamed) {
  expectInputError([&] { loadParameters("/nonexistent/p.json"); }, {"/nonexistent/p.json", "cannot open"});
}

}  // namespace
}  // namespace colosim
