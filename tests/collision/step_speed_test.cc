// The world step's speed work (issue 18): two lanes give the same bits as one, and a step
// allocates no memory once running. Its own executable: it replaces the global operator
// new to count allocations.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <thread>

#include <gtest/gtest.h>

#include "collision/contact_query.h"
#include "core/step_lanes.h"
#include "fixture.h"
#include "trainer/assets.h"
#include "step.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t bytes) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(bytes ? bytes : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace colosim {
namespace {

WorldModel adultWorld() {
  const Parameters p = loadParameters(test::asset("params/default.json"));
  return loadWorldModel(test::asset("anatomy/adult.json"), p);
}

// The handle at step k of a scripted insertion with a turn: the scope moves against the
// wall, so contacts come and go.
HandleInput scripted(const HandleInput& start, int k) {
  HandleInput in = start;
  in.insertion_m += 0.02 * kDt * k;                 // 2 cm/s
  in.rotation_rad += 0.5 * std::sin(2e-3 * k);      // +-0.5 rad
  in.knob_updown_rad = 0.8 * std::sin(3e-3 * k);
  return in;
}

TEST(StepLanes, RunsBothTasksEveryTime) {
  StepLanes lanes;
  long a = 0, b = 0;
  for (int i = 0; i < 20000; ++i) lanes.run([&] { ++a; }, [&] { ++b; });
  EXPECT_EQ(a, 20000);
  EXPECT_EQ(b, 20000);
  EXPECT_EQ(lanes.workerRan() + lanes.callerTookBack(), 20000);
}

// The lanes poll for 200 us before they sleep: tasks posted after longer pauses find the
// worker asleep and must wake it; tasks posted back to back find it polling. Either way
// every task runs once, and a task may wait for a flag the other lane sets (the world
// step's scope waits so for the colon's wall speed).
TEST(StepLanes, HandsOverAfterTheWorkerHasSleptAndWaitsForTheOtherLane) {
  StepLanes lanes;
  long a = 0, b = 0;
  for (int i = 0; i < 40; ++i) {
    if (i % 2 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    std::atomic<bool> ready{false};
    long seen = -1;
    lanes.run(
        [&] {
          waitUntilSet(ready);
          seen = b;
          ++a;
        },
        [&] {
          ++b;
          ready.store(true, std::memory_order_release);
        });
    EXPECT_EQ(seen, b) << "iteration " << i;  // the waiting task saw the other's work
  }
  EXPECT_EQ(a, 40);
  EXPECT_EQ(b, 40);
  EXPECT_EQ(lanes.workerRan() + lanes.callerTookBack(), 40);
}

TEST(StepLanes, TwoLanesGiveTheSameStatesAsOne) {
  const WorldModel m = adultWorld();
  WorldState one = makeWorldState(m);
  threadScopeAlongColon(m, one, 0.6);
  WorldState two = one;
  FclContactQuery q1(m), q2(m);
  StepLanes lanes;
  const HandleInput start = one.scope.input;
  size_t contacts = 0;
  for (int k = 0; k < 600; ++k) {
    stepWorld(m, one, scripted(start, k), q1, kDt);
    stepWorld(m, two, scripted(start, k), q2, kDt, &lanes);
    contacts += one.wall.size() + one.self.size();
    if (k % 50 == 49) {
      ASSERT_EQ(hashWorldState(one), hashWorldState(two)) << "step " << k;
    }
  }
  EXPECT_GT(contacts, 600u);  // the comparison covered steps with contacts
  EXPECT_EQ(one.wall.size(), two.wall.size());
  EXPECT_EQ(one.self.size(), two.self.size());
}

// The broadphase's fat bounds (a Verlet list, updated only when the colon or the scope has
// moved by the margin) give the states of bounds updated at every step, bit for bit, while
// the scope is pushed, turned and steered against the wall; and they do skip updates.
TEST(FatBounds, GiveTheSameStatesAsBoundsUpdatedEveryStep) {
  const WorldModel m = adultWorld();
  WorldState exact = makeWorldState(m);
  threadScopeAlongColon(m, exact, 0.6);
  WorldState fat = exact, fatter = exact;
  FclContactQuery q_exact(m, "dynamic_aabb_tree", 0.0), q_fat(m), q_fatter(m, "dynamic_aabb_tree", 0.02);
  const HandleInput start = exact.scope.input;
  const int steps = 1500;
  size_t contacts = 0;
  for (int k = 0; k < steps; ++k) {
    const HandleInput in = scripted(start, k);
    stepWorld(m, exact, in, q_exact, kDt);
    stepWorld(m, fat, in, q_fat, kDt);
    stepWorld(m, fatter, in, q_fatter, kDt);
    contacts += exact.wall.size() + exact.self.size();
    if (k % 50 == 49) {
      ASSERT_EQ(hashWorldState(fat), hashWorldState(exact)) << "step " << k;
      ASSERT_EQ(hashWorldState(fatter), hashWorldState(exact)) << "step " << k;
    }
  }
  EXPECT_GT(contacts, static_cast<size_t>(steps));  // the comparison covered steps with contacts
  EXPECT_EQ(q_exact.wallRebuilds(), steps);
  EXPECT_EQ(q_exact.selfRebuilds(), steps);
  EXPECT_LT(q_fat.wallRebuilds(), steps / 2);
  EXPECT_LT(q_fat.selfRebuilds(), steps / 2);
  EXPECT_LT(q_fatter.wallRebuilds(), q_fat.wallRebuilds());
  std::printf("updates of the broadphase over %d steps: wall %ld (fat 2 mm), %ld (20 mm); self %ld, %ld\n", steps,
              q_fat.wallRebuilds(), q_fatter.wallRebuilds(), q_fat.selfRebuilds(), q_fatter.selfRebuilds());
}

// Once running (its vectors at their sizes), a step of the world allocates nothing: FCL's
// broadphase update and query, the tracking, the forces and both solves, on one lane and
// on two.
TEST(StepAllocations, AStepAllocatesNothingOnceRunning) {
  const WorldModel m = adultWorld();
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, m.colon.length_m() - 0.02);
  FclContactQuery q(m);
  StepLanes lanes;
  const HandleInput start = s.scope.input;
  for (int k = 0; k < 300; ++k) stepWorld(m, s, start, q, kDt);
  for (StepLanes* l : {static_cast<StepLanes*>(nullptr), &lanes}) {
    for (int k = 0; k < 20; ++k) stepWorld(m, s, start, q, kDt, l);  // warm (the lanes' first runs)
    g_allocations = 0;
    g_counting = true;
    for (int k = 0; k < 200; ++k) stepWorld(m, s, start, q, kDt, l);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0) << (l ? "two lanes" : "one lane");
    EXPECT_GT(s.wall.size(), 20u);
  }
  // Moving (the broadphase updated now and then): after the same warm-up, nothing either.
  const long updates_before = q.wallRebuilds();
  for (int k = 0; k < 300; ++k) stepWorld(m, s, scripted(start, -k), q, kDt);
  g_allocations = 0;
  g_counting = true;
  for (int k = 300; k < 500; ++k) stepWorld(m, s, scripted(start, -k), q, kDt);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0) << "moving";
  EXPECT_GT(q.wallRebuilds() - updates_before, 10);
}

// ... nor with the contacts' coupling predictor on (ContactParams::coupling_predictor): its
// limit's stiffness sums live in the state, sized by makeWorldState.
TEST(StepAllocations, WithTheCouplingPredictorAStepAllocatesNothing) {
  Parameters p = loadParameters(test::asset("params/default.json"));
  p.contact.coupling_predictor = true;
  const WorldModel m = loadWorldModel(test::asset("anatomy/adult.json"), p);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, m.colon.length_m() - 0.02);
  FclContactQuery q(m);
  const HandleInput start = s.scope.input;
  for (int k = 0; k < 300; ++k) stepWorld(m, s, scripted(start, -k), q, kDt);
  g_allocations = 0;
  g_counting = true;
  for (int k = 300; k < 500; ++k) stepWorld(m, s, scripted(start, -k), q, kDt);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(s.wall.size(), 20u);
}

// The counter counts: a step from a fresh query (its scratch vectors empty) allocates.
TEST(StepAllocations, TheCounterSeesAFreshQuerysAllocations) {
  const WorldModel m = adultWorld();
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, 0.6);
  FclContactQuery q(m);
  g_allocations = 0;
  g_counting = true;
  stepWorld(m, s, s.scope.input, q, kDt);
  g_counting = false;
  EXPECT_GT(g_allocations.load(), 0);
}

}  // namespace
}  // namespace colosim
