// The handle force a replay feels at the simulator's 1 ms against a step four times finer,
// and the contact coupling's predictor against the coupled step it stands for
// (ContactParams::coupling_predictor, coupling_sweeps; docs/numerics.md, "The contacts'
// coupling"). The colon and the scope are each solved with the other held. With the other
// body's part of a contact held over the step, the other's push arrives a step late: through
// the quick push of the organ trials' two-rate protocol the 1 ms force then stands 1-1.5 N
// off the converged one, with a dip of about 1 N each time a scope segment goes in.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "identify/insertion/replay.h"
#include "identify/insertion/synthetic.h"
#include "trainer/scenario.h"

namespace colosim {
namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Seed 1004's two-rate protocol: a slow push from 40 cm, a hold, a quick push of 4.6 cm at
// 0.23 m/s (0.90-1.10 s), a hold and a withdrawal; the paper's model, nothing hidden, made and
// replayed with the predictor on or off.
struct QuickPush {
  ReplaySetup setup;
  InsertionRecording rec;
};
QuickPush quickPush(bool predictor) {
  QuickPush q{makeReplaySetup(findScenario("free_insertion_attached_rectum")), {}};
  q.setup.params.contact.coupling_predictor = predictor;
  q.rec = makeSyntheticInsertion(q.setup, drawTwoRateInsertion(1004, -1, 2.0));
  return q;
}

// |a - b| over the quick push's rows, less the two where the handle's velocity jumps (there
// the grip's inertial impulse grows as 1 / dt, a step's worth whatever the coupling), and
// over every row.
struct Differences {
  std::vector<double> push, all;
  double largest_push = 0;
};
Differences differences(const InsertionRecording& rec, const Prediction& a, const Prediction& b) {
  Differences d;
  for (size_t r = 0; r < rec.rows(); ++r) {
    const double x = std::abs(a.force_N[r] - b.force_N[r]);
    if (rec.time_s[r] > 0.905 && rec.time_s[r] < 1.095) {
      d.push.push_back(x);
      d.largest_push = std::max(d.largest_push, x);
    }
    d.all.push_back(x);
  }
  return d;
}

// The predictor as landed is limited where both bodies are light against their contacts
// (applyWallContacts): unlimited, it ran the quick push within 0.053 N of the quarter step but
// grew without bound where the wall's backing engaged (docs/numerics.md). Measured limited:
// quick push median 0.198 N, largest 0.60 N, every row 0.208 N; lagging 1.306, 2.61 and
// 0.471 N.
TEST(ContactCoupling, AQuickPushFeelsAtOneMillisecondWhatItFeelsAtAQuarterWithThePredictor) {
  Differences lagging, predicted;
  for (bool predictor : {false, true}) {
    const QuickPush q = quickPush(predictor);
    ASSERT_DOUBLE_EQ(q.setup.dt_s, 0.001);
    const Prediction coarse = replayInsertion(q.setup, q.rec, OrganParams());
    ReplaySetup fine_setup = q.setup;
    fine_setup.dt_s = 0.00025;
    const Prediction fine = replayInsertion(fine_setup, q.rec, OrganParams());
    ASSERT_TRUE(coarse.ok);
    ASSERT_TRUE(fine.ok);
    const Differences d = differences(q.rec, coarse, fine);
    ASSERT_GE(d.push.size(), 15u);
    std::printf("predictor %s: 1 ms against 0.25 ms, quick push median %.3f N, largest %.3f N; every row median %.3f N\n",
                predictor ? "on " : "off", median(d.push), d.largest_push, median(d.all));
    (predictor ? predicted : lagging) = d;
  }
  EXPECT_GT(median(lagging.push), 0.8) << "the lag is no longer seen: revisit docs/numerics.md";
  EXPECT_LT(median(predicted.push), 0.25 * median(lagging.push));
  EXPECT_LT(predicted.largest_push, 0.5 * lagging.largest_push);
  EXPECT_LT(median(predicted.all), 0.6 * median(lagging.all));
}

// The coupled step: eight sweeps from the lagging solve, each body again with the other's
// actual move (a block Jacobi iteration on the two bodies' joint step). The predictor lands
// nearer to it than the lag. Measured, median over the quick push: predictor 0.113 N, lag
// 1.504 N; every row 0.066 against 0.460 N.
TEST(ContactCoupling, ThePredictorLandsNearTheCoupledStep) {
  const QuickPush q = quickPush(true);
  const Prediction predicted = replayInsertion(q.setup, q.rec, OrganParams());
  ReplaySetup coupled = q.setup, lagging = q.setup;
  coupled.params.contact.coupling_predictor = false;
  coupled.params.contact.coupling_sweeps = 8;
  lagging.params.contact.coupling_predictor = false;
  const Prediction swept = replayInsertion(coupled, q.rec, OrganParams());
  const Prediction lagged = replayInsertion(lagging, q.rec, OrganParams());
  ASSERT_TRUE(predicted.ok);
  ASSERT_TRUE(swept.ok);
  ASSERT_TRUE(lagged.ok);
  const Differences d = differences(q.rec, predicted, swept), l = differences(q.rec, lagged, swept);
  std::printf("against eight sweeps: predictor quick push median %.3f N, largest %.3f N, every row %.3f N; "
              "lag %.3f N, %.3f N, %.3f N\n",
              median(d.push), d.largest_push, median(d.all), median(l.push), l.largest_push, median(l.all));
  EXPECT_LT(median(d.push), 0.25 * median(l.push));
  EXPECT_LT(median(d.all), 0.5 * median(l.all));
}

}  // namespace
}  // namespace colosim
