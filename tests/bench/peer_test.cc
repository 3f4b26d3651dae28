// colosim bench peer (bench/bench_peer.h): a short run prints the keys with
// finite values, and a build without MuJoCo says so with exit status 2.
#include "bench/bench_peer.h"

#include <cmath>

#include <gtest/gtest.h>

namespace colosim {
namespace {

TEST(BenchPeer, ShortRunReportsBothStepTimesAndTheDifferences) {
  PeerOptions o;
  o.duration_s = 0.05;  // 50 steps of the script
  o.block_steps = 10;
  const BenchOutput out = benchPeer(o);
  if (!peerAvailable()) {
    EXPECT_EQ(out.exit_code, 2);
    EXPECT_NE(out.error.find("MuJoCo is not installed"), std::string::npos) << out.error;
    return;
  }
  ASSERT_EQ(out.exit_code, 0) << out.error;
  for (const char* key : {"colosim_step_us", "mujoco_step_us", "speed_ratio", "tip_rms_difference_m",
                          "handle_force_rms_difference_N"}) {
    ASSERT_TRUE(out.json.contains(key)) << key;
    const double v = out.json[key].get<double>();
    EXPECT_TRUE(std::isfinite(v) && v >= 0) << key << " = " << v;
  }
  EXPECT_EQ(out.json["steps"].get<int>(), 50);
  EXPECT_GT(out.json["colosim_step_us"].get<double>(), 0);
  EXPECT_GT(out.json["mujoco_step_us"].get<double>(), 0);
  EXPECT_NEAR(out.json["speed_ratio"].get<double>(),
              out.json["mujoco_step_us"].get<double>() / out.json["colosim_step_us"].get<double>(), 1e-9);
  // Both start from the same threaded pose: the tips agree at the start. The first 50 ms
  // are the threaded scope settling against the wall, which the two settle differently
  // (13 mm rms apart when written; over the whole 10 s, 8 mm).
  EXPECT_LT(out.json["tip_start_difference_m"].get<double>(), 1e-6);
  EXPECT_LT(out.json["tip_rms_difference_m"].get<double>(), 0.025);
  EXPECT_NE(out.text.find("speed ratio MuJoCo / colosim"), std::string::npos);
}

TEST(BenchPeer, RefusesANonPositiveDuration) {
  PeerOptions o;
  o.duration_s = 0;
  if (!peerAvailable()) GTEST_SKIP() << "no MuJoCo in this build";
  EXPECT_THROW(benchPeer(o), std::invalid_argument);
}

}  // namespace
}  // namespace colosim
