// The insertion report (identify/insertion/report.h): the data behind the plots carries each model's
// prediction with its fitted offset and the push / hold / pull class of every row, and
// gnuplot draws the three PNGs. No simulation: the predictions are written in.
#include "identify/insertion/report.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "fixture.h"

namespace colosim {
namespace {

TEST(OrganReport, WritesThePlotsAndTheirDataWithOffsetsAndMotion) {
  // 60 rows at 10 ms: push at 5 cm/s for 0.3 s, hold 0.1 s, pull at 5 cm/s.
  InsertionRecording rec;
  rec.file = "synthetic.csv";
  rec.scenario = "free_insertion";
  double ins = 0.1;
  for (int k = 0; k < 60; ++k) {
    const double t = 0.01 * k;
    if (k > 0) ins += t <= 0.3 ? 5e-4 : (t <= 0.4 ? 0.0 : -5e-4);
    rec.time_s.push_back(t);
    HandleInput in;
    in.insertion_m = ins;
    rec.input.push_back(in);
    rec.force_N.push_back(1.0 + 2.0 * (ins - 0.1) + 0.01 * (k % 3));  // [N]
    rec.torque_Nm.push_back(0.002 * k);                               // [N m]
  }
  InsertionIdentifyResult r;
  r.effects = {"colon_bending"};
  r.baseline.prediction.force_N.assign(60, 0.5);  // offset 0.7 N on average
  r.baseline.prediction.torque_Nm.assign(60, 0.0);
  r.baseline.offset_N = 0.7;
  r.baseline.offset_Nm = 0.01;
  r.extended = r.baseline;
  r.extended.effects = r.effects;
  r.extended.params.bending_EI_Nm2 = 0.02;
  r.extended.prediction.force_N = rec.force_N;
  r.extended.prediction.torque_Nm = rec.torque_Nm;
  r.extended.offset_N = 0.0;
  r.extended.offset_Nm = 0.0;

  test::TempDir dir;
  const std::string out = dir.file("report");
  writeOrganReport(out, rec, r);

  std::ifstream dat(out + "/insertion.dat");
  std::string line;
  int rows = 0, push = 0, hold = 0, pull = 0;
  while (std::getline(dat, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    double t, x, fm, fb, fx, tm, tb, tx, rb, rx;
    int motion;
    in >> t >> x >> motion >> fm >> fb >> fx >> tm >> tb >> tx >> rb >> rx;
    ASSERT_TRUE(in) << line;
    EXPECT_NEAR(fb, 0.5 + 0.7, 1e-5);          // prediction + fitted offset [N]
    EXPECT_NEAR(tb, 0.01, 1e-6);               // [N m]
    EXPECT_NEAR(fx, fm, 1e-5);
    EXPECT_NEAR(rb, fm - 1.2, 1e-5);           // residual of the paper's model [N]
    EXPECT_NEAR(rx, 0.0, 1e-5);
    push += motion == 0, hold += motion == 1, pull += motion == 2;
    ++rows;
  }
  EXPECT_EQ(rows, 60);
  EXPECT_GE(push, 28);  // rows 1-29 push, 31-39 hold, 41-58 pull (the edges may be hold)
  EXPECT_GE(hold, 8);
  EXPECT_GE(pull, 17);
  for (const char* png : {"force_time.png", "force_depth.png", "residuals.png"}) {
    const std::string bytes = test::readFile(out + "/" + png);
    ASSERT_GT(bytes.size(), 1000u) << png;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << png;
  }
  EXPECT_NE(test::readFile(out + "/report.gp").find("colon_bending 0.02 N m^2"), std::string::npos);
  EXPECT_NE(test::readFile(out + "/identify.json").find("\"experiment\": \"insertion\""), std::string::npos);
}

}  // namespace
}  // namespace colosim
