// The refinement's replay pool (identify/insertion/replay_pool.h): a free thread runs the
// replays the search will probably ask for next. What it returns must be what a replay
// started when asked returns, bit for bit, and guesses that are not asked for must not
// leak into any answer.
#include <atomic>

#include <gtest/gtest.h>

#include "identify/insertion/replay_pool.h"
#include "identify/insertion/synthetic.h"
#include "trainer/scenario.h"

namespace colosim {
namespace {

OrganParams bending(double ei_Nm2) {
  OrganParams p;
  p.bending_EI_Nm2 = ei_Nm2;
  return p;
}

void expectSameBits(const Prediction& a, const Prediction& b) {
  EXPECT_EQ(a.ok, b.ok);
  EXPECT_EQ(a.force_N, b.force_N);
  EXPECT_EQ(a.torque_Nm, b.torque_Nm);
  ASSERT_EQ(a.tip_m.size(), b.tip_m.size());
  for (size_t k = 0; k < a.tip_m.size(); ++k) EXPECT_EQ(a.tip_m[k], b.tip_m[k]) << "row " << k;
}

TEST(ReplayPool, AGuessedReplayIsTheReplayAskedForAndOneNotAskedForIsDropped) {
  const ReplaySetup setup = makeReplaySetup(findScenario("free_insertion_attached_rectum"), 0.03);
  const InsertionRecording rec = makeSyntheticInsertion(setup, drawSyntheticInsertion(7, 0, 0.5));
  const Prediction direct_a = replayInsertion(setup, rec, bending(0.01));
  const Prediction direct_b = replayInsertion(setup, rec, bending(0.02));
  const Prediction direct_c = replayInsertion(setup, rec, bending(0.04));

  ReplayPool pool(setup, rec, 2);
  int guesses = 0;
  // One replay asked on two threads: the other thread is free from the start, so the pool
  // asks for a guess at once.
  const std::vector<Prediction> first = pool.run({bending(0.01)}, [&](const std::vector<const Prediction*>& done) {
    ++guesses;
    EXPECT_EQ(done.size(), 1u);
    return std::vector<OrganParams>{bending(0.02), bending(0.03)};
  });
  EXPECT_GE(guesses, 1);
  ASSERT_EQ(first.size(), 1u);
  expectSameBits(first[0], direct_a);
  // Asked for next: the guess, whether it ran already, is running or never started.
  const std::vector<Prediction> second = pool.run({bending(0.02), bending(0.04)});
  ASSERT_EQ(second.size(), 2u);
  expectSameBits(second[0], direct_b);
  expectSameBits(second[1], direct_c);
  EXPECT_LE(pool.guessesUsed(), 1);
  EXPECT_LE(pool.guessesUsed(), pool.guessesStarted());
  EXPECT_LE(pool.guessesStarted(), 2);
}

TEST(ReplayPool, ACancelledReplayStopsAndIsNotOk) {
  const ReplaySetup setup = makeReplaySetup(findScenario("free_insertion_attached_rectum"), 0.03);
  const InsertionRecording rec = makeSyntheticInsertion(setup, drawSyntheticInsertion(7, 0, 0.5));
  std::atomic<bool> cancel{true};
  EXPECT_FALSE(replayInsertion(setup, rec, bending(0.01), &cancel).ok);
  cancel = false;
  EXPECT_TRUE(replayInsertion(setup, rec, bending(0.01), &cancel).ok);
}

}  // namespace
}  // namespace colosim
