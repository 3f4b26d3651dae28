// Clinical directions a design study must reproduce (issue 20 item 4), as small studies on
// the one patient (params/default.json): whole scenarios, scripted, seed 0.
#include <algorithm>
#include <cstdio>

#include <gtest/gtest.h>

#include "trainer/study.h"

namespace colosim {
namespace {

double metricOf(const CaseResult& c, const std::string& name) {
  const std::vector<std::string>& names = studyMetricNames();
  const size_t i = static_cast<size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  EXPECT_LT(i, names.size()) << name;
  EXPECT_TRUE(c.metrics.at(i).has_value()) << name;
  return c.metrics.at(i).value_or(0.0);
}

// Guided, front-pulled scopes show 30-40 % lower peak forces clinically. On the alpha loop
// pushed into (sigmoid_push, 26 s of pushing without torque), the follow-the-leader scope,
// whose joints take the bends the tip had at their depth, must press the wall and stretch
// the mesentery less than the passive scope driven by the same hand.
TEST(DesignDirections, FollowTheLeaderLowersPeakWallForceAndMesenteryStretch) {
  const std::string text = R"({
    "format": "colosim-study", "version": 1, "name": "ftl_direction", "description": "test",
    "designs": [{"name": "passive", "scope": "scopes/standard.json"},
                {"name": "follow_the_leader", "scope": "scopes/follow_the_leader.json"}],
    "scenarios": ["sigmoid_push"], "strategies": ["scripted"], "seeds": [0]})";
  const Study s = parseStudy(text, "ftl_direction.json");
  const std::vector<CaseResult> r = runStudyCases(s, studyCases(s), 2);
  ASSERT_EQ(r.size(), 2u);
  const double wall_passive = metricOf(r[0], "peak_wall_force_N"), wall_ftl = metricOf(r[1], "peak_wall_force_N");
  const double stretch_passive = metricOf(r[0], "peak_mesentery_stretch");
  const double stretch_ftl = metricOf(r[1], "peak_mesentery_stretch");
  std::printf("peak wall force %.2f -> %.2f N (%+.0f %%), peak mesentery stretch %.2f -> %.2f (%+.0f %%), "
              "peak handle force %.2f -> %.2f N\n",
              wall_passive, wall_ftl, 100 * (wall_ftl / wall_passive - 1), stretch_passive, stretch_ftl,
              100 * (stretch_ftl / stretch_passive - 1), metricOf(r[0], "peak_handle_force_N"),
              metricOf(r[1], "peak_handle_force_N"));
  EXPECT_LT(wall_ftl, wall_passive);
  EXPECT_LT(stretch_ftl, stretch_passive);
}

}  // namespace
}  // namespace colosim
