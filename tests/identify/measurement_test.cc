// The measurement reader (identify/measurement.h): every bad file is an InputError
// naming the file and line.
#include "identify/measurement.h"
#include "identify/tension/tension_test.h"

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "fixture.h"

namespace colosim {
namespace {

std::string goodText(int rows = 40) {
  std::string s = "# colosim-measurement v1\n# experiment: tension\n# sample_length_m: 0.18\n# note: a, b: c\n"
                  "time_s,elongation_m,force_N\n";
  for (int k = 0; k < rows; ++k) s += std::to_string(0.1 * k) + "," + std::to_string(0.001 * k) + ",0.5\n";
  return s;
}

// Expects InputError with "file:line" and `what` in the message.
void expectBad(const std::string& text, int line, const std::string& what) {
  test::TempDir dir;
  const std::string path = dir.write("bad.csv", text);
  try {
    readTensionTest(path);
    ADD_FAILURE() << "no error for: " << what;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path + (line > 0 ? ":" + std::to_string(line) + ":" : "")), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

std::string replaceLine(std::string text, int line, const std::string& with) {
  size_t a = 0;
  for (int k = 1; k < line; ++k) a = text.find('\n', a) + 1;
  const size_t b = text.find('\n', a);
  return text.substr(0, a) + with + text.substr(b);
}

TEST(Measurement, ReadsHeaderMetadataAndColumns) {
  test::TempDir dir;
  const TensionTest t = readTensionTest(dir.write("ok.csv", goodText()));
  EXPECT_EQ(t.rows(), 40u);
  EXPECT_DOUBLE_EQ(t.sample_length_m, 0.18);
  ASSERT_EQ(t.metadata.size(), 1u);
  EXPECT_EQ(t.metadata[0].first, "note");
  EXPECT_EQ(t.metadata[0].second, "a, b: c");
  EXPECT_DOUBLE_EQ(t.elongation_m[3], 0.003);
}

TEST(Measurement, WriteThenReadGivesTheSameTest) {
  test::TempDir dir;
  TensionTest t;
  t.sample_length_m = 0.18;
  t.metadata = {{"source", "synthetic"}};
  for (int k = 0; k < 50; ++k) {
    t.time_s.push_back(0.25 * k);
    t.elongation_m.push_back(1e-3 * k);
    t.force_N.push_back(0.0125 * k);
  }
  writeTensionTest(dir.file("t.csv"), t);
  const TensionTest u = readTensionTest(dir.file("t.csv"));
  ASSERT_EQ(u.rows(), t.rows());
  for (size_t k = 0; k < t.rows(); ++k) {  // to the decimals the file keeps
    EXPECT_NEAR(u.time_s[k], t.time_s[k], 1e-12);
    EXPECT_NEAR(u.elongation_m[k], t.elongation_m[k], 1e-12);
    EXPECT_NEAR(u.force_N[k], t.force_N[k], 1e-12);
  }
  EXPECT_EQ(u.metadata, t.metadata);
}

TEST(Measurement, GenericReaderTakesOtherExperimentsAndColumns) {
  test::TempDir dir;
  std::string s = "# colosim-measurement v1\n# experiment: insertion\n# scope: CF-HQ190L\n"
                  "time_s,insertion_m,force_N,torque_Nm\n";
  for (int k = 0; k < 40; ++k) s += std::to_string(0.1 * k) + ",0.01,1.5,0.02\n";
  MeasurementSpec spec;
  spec.required_keys = {"experiment", "scope"};
  spec.columns = {"time_s", "insertion_m", "force_N", "torque_Nm"};
  const Measurement m = readMeasurement(dir.write("ins.csv", s), spec);
  EXPECT_EQ(m.meta("scope"), "CF-HQ190L");
  EXPECT_EQ(m.column("torque_Nm").size(), 40u);
  EXPECT_THROW(m.column("angle_rad"), InputError);
  EXPECT_THROW(readTensionTest(dir.file("ins.csv")), InputError);
}

TEST(Measurement, BadFilesNameTheFileAndLine) {
  const std::string g = goodText();
  expectBad("", 1, "empty file");
  expectBad(replaceLine(g, 1, "# colosim-measurement v2"), 1, "colosim-measurement v1");
  expectBad(replaceLine(g, 2, "# note2: nothing"), 5, "missing header line '# experiment");
  expectBad(replaceLine(g, 3, "# other: 1"), 5, "missing header line '# sample_length_m");
  expectBad(replaceLine(g, 3, "# sample_length_m: -0.18"), 0, "sample_length_m");
  expectBad(replaceLine(g, 3, "# sample_length_m: 18cm"), 0, "sample_length_m");
  expectBad(replaceLine(g, 2, "# experiment: insertion"), 0, "must be 'tension'");
  expectBad(replaceLine(g, 4, "# experiment: tension"), 4, "appears twice");
  expectBad(replaceLine(g, 4, "# no colon here"), 4, "'# key: value'");
  expectBad(replaceLine(g, 5, "time_s,force_N,elongation_m"), 5, "columns must be 'time_s,elongation_m,force_N'");
  expectBad(replaceLine(g, 5, "time_s,elongation_m"), 5, "columns must be");
  expectBad(replaceLine(g, 5, "time_s,elongation_m,force_N,extra"), 5, "columns must be");
  expectBad(replaceLine(g, 10, "0.4,0.004"), 10, "expected 3 values, got 2");
  expectBad(replaceLine(g, 10, "0.4,0.004,0.5,7"), 10, "expected 3 values, got 4");
  expectBad(replaceLine(g, 10, "0.2,0.004,0.5"), 10, "time_s must increase strictly");
  expectBad(replaceLine(g, 10, "0.3,0.004,0.5"), 10, "time_s must increase strictly");
  expectBad(replaceLine(g, 10, "0.4,nan,0.5"), 10, "not finite");
  expectBad(replaceLine(g, 10, "0.4,0.004,inf"), 10, "not finite");
  expectBad(replaceLine(g, 10, "0.4,0.004,"), 10, "is not a number");
  expectBad(replaceLine(g, 10, "0.4,4mm,0.5"), 10, "is not a number");
  expectBad(replaceLine(g, 10, "# a comment"), 10, "header line after the column line");
  expectBad(replaceLine(g, 10, ""), 10, "blank line");
  expectBad(goodText(35), 40, "only 35 data rows, need at least 36");
  expectBad("# colosim-measurement v1\n# experiment: tension\n# sample_length_m: 0.18\n", 3, "no column line");
  // Truncated in the middle of a row.
  std::string cut = g.substr(0, g.size() - 5);
  expectBad(cut, 45, "expected 3 values");
}

TEST(Measurement, MissingFileIsAnInputError) {
  EXPECT_THROW(readTensionTest("/nonexistent/colosim/measurement.csv"), InputError);
}

TEST(Measurement, WindowsLineEndingsAreRead) {
  std::string g = goodText(), crlf;
  for (char c : g) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  test::TempDir dir;
  EXPECT_EQ(readTensionTest(dir.write("crlf.csv", crlf)).rows(), 40u);
}

}  // namespace
}  // namespace colosim
