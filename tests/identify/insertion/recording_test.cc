// Recorded insertions: the reader's bad-input cases and a write/read round trip.
#include "identify/insertion/recording.h"

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "fixture.h"

namespace colosim {
namespace {

std::string header(const std::string& extra = "") {
  return "# colosim-measurement v1\n# experiment: insertion\n# scenario: free_insertion\n" + extra +
         "time_s,insertion_m,rotation_rad,knob_updown_rad,knob_leftright_rad,handle_force_N,handle_torque_Nm\n";
}
std::string rows(int n, int bad_row = -1, const std::string& bad = "") {
  std::string s;
  for (int k = 0; k < n; ++k) {
    if (k == bad_row) { s += bad + "\n"; continue; }
    s += std::to_string(0.01 * k) + "," + std::to_string(0.1 + 0.001 * k) + ",0.1,0.2,0,0.5,0.01\n";
  }
  return s;
}

void expectError(const std::string& path, const std::string& needle) {
  try {
    readInsertionRecording(path);
    FAIL() << "no error for " << needle;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(needle), std::string::npos) << what;
  }
}

TEST(InsertionRecording, ReadsAGoodFileAndRoundTrips) {
  test::TempDir dir;
  const std::string f = dir.write("a.csv", header("# note: bench 3\n") + rows(40));
  const InsertionRecording r = readInsertionRecording(f);
  EXPECT_EQ(r.rows(), 40u);
  EXPECT_EQ(r.scenario, "free_insertion");
  EXPECT_FALSE(r.has_tip);
  EXPECT_DOUBLE_EQ(r.input[3].insertion_m, 0.103);
  EXPECT_DOUBLE_EQ(r.force_N[0], 0.5);
  EXPECT_EQ(measurementExperiment(f), "insertion");
  // Interpolated inputs between rows.
  EXPECT_NEAR(recordedInput(r, 0.015).insertion_m, 0.1015, 1e-12);
  const std::string g = dir.file("b.csv");
  writeInsertionRecording(g, r);
  const InsertionRecording s = readInsertionRecording(g);
  EXPECT_EQ(s.rows(), r.rows());
  EXPECT_EQ(s.metadata.back().second, "bench 3");
}

TEST(InsertionRecording, ReadsTheOptionalTipColumns) {
  test::TempDir dir;
  std::string text = "# colosim-measurement v1\n# experiment: insertion\n# scenario: free_insertion\n"
                     "time_s,insertion_m,rotation_rad,knob_updown_rad,knob_leftright_rad,handle_force_N,"
                     "handle_torque_Nm,tip_x_m,tip_y_m,tip_z_m\n";
  for (int k = 0; k < 40; ++k) text += std::to_string(0.01 * k) + ",0.1,0,0,0,0.5,0.01,0.01,0.02,0.1\n";
  const InsertionRecording r = readInsertionRecording(dir.write("t.csv", text));
  ASSERT_TRUE(r.has_tip);
  EXPECT_DOUBLE_EQ(r.tip_m[5].y(), 0.02);
}

TEST(InsertionRecording, BadFilesNameTheFileAndLine) {
  test::TempDir dir;
  expectError(dir.write("noscen.csv", "# colosim-measurement v1\n# experiment: insertion\n"
                                      "time_s,insertion_m,rotation_rad,knob_updown_rad,knob_leftright_rad,"
                                      "handle_force_N,handle_torque_Nm\n" + rows(40)),
              "scenario");
  expectError(dir.write("exp.csv", "# colosim-measurement v1\n# experiment: tension\n# scenario: x\n"
                                   "time_s,insertion_m,rotation_rad,knob_updown_rad,knob_leftright_rad,"
                                   "handle_force_N,handle_torque_Nm\n" + rows(40)),
              "insertion");
  expectError(dir.write("cols.csv", "# colosim-measurement v1\n# experiment: insertion\n# scenario: x\n"
                                    "time_s,insertion_m,rotation_rad,handle_force_N,handle_torque_Nm\n" + rows(40)),
              "column");
  expectError(dir.write("few.csv", header() + rows(10)), "rows");
  expectError(dir.write("nan.csv", header() + rows(40, 7, "0.07,0.1,nan,0,0,0.5,0.01")), ":12");
  expectError(dir.write("time.csv", header() + rows(40, 7, "0.01,0.1,0,0,0,0.5,0.01")), ":12");
  expectError(dir.write("neg.csv", header() + rows(40, 5, "0.05,-0.1,0,0,0,0.5,0.01")), ":10: insertion_m");
  expectError(dir.write("knob.csv", header() + rows(40, 5, "0.05,0.1,0,4,0,0.5,0.01")), ":10: knob_updown");
  expectError(dir.write("unit.csv", header() + rows(40, 5, "0.05,0.1,0,0,0,5000,0.01")), ":10: handle_force_N");
  expectError(dir.write("short.csv", header() + rows(40, 5, "0.05,0.1,0,0")), ":10");
}

}  // namespace
}  // namespace colosim
