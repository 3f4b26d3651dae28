#include "core/step_lanes.h"

#include <chrono>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace colosim {

namespace {

enum : long { kIdle = 0, kPosted = 1, kClaimed = 2, kDone = 3 };
inline long tagged(long generation, long phase) { return 4 * generation + phase; }

// How long a lane keeps polling before it sleeps [us]. A world step's halves take tens of
// microseconds and follow each other within a step and from step to step, so a lane that
// polls this long finds the next task without a futex wake (which cost more than the
// halves saved: docs/performance.md); a lane with nothing to do sleeps after it.
constexpr auto kPoll = std::chrono::microseconds(200);

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

// Polls `done()` for up to kPoll; true when it became true.
template <class F>
bool pollFor(F&& done) {
  if (done()) return true;
  const auto until = std::chrono::steady_clock::now() + kPoll;
  for (int k = 1;; ++k) {
    relax();
    if (done()) return true;
    if (k % 64 == 0 && std::chrono::steady_clock::now() > until) return done();
  }
}

}  // namespace

void waitUntilSet(const std::atomic<bool>& flag) {
  for (int k = 0; !flag.load(std::memory_order_acquire); ++k) {
    if (k < 4096)
      relax();
    else
      std::this_thread::yield();
  }
}

StepLanes::StepLanes() : worker_([this] { loop(); }) {}

StepLanes::~StepLanes() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_one();
  worker_.join();
}

// The hand-overs without a lock: the caller publishes a task (its two pointers, then the
// generation) and the worker claims it by compare-and-swap on state_; either side sleeps
// only after polling for kPoll, and says so in a flag (`worker_sleeping_`,
// `caller_sleeping_`) set under the mutex before it checks its condition a last time. The
// other side stores its news and then reads the flag (all sequentially consistent), so
// one of the two always sees the other: a sleeper is woken, or it never sleeps.
void StepLanes::loop() {
  long seen = 0;
  for (;;) {
    auto posted = [&] { return stop_.load() || posted_.load() != seen; };
    if (!pollFor(posted)) {
      std::unique_lock<std::mutex> lock(mutex_);
      worker_sleeping_.store(true);
      wake_.wait(lock, posted);
      worker_sleeping_.store(false);
    }
    if (stop_.load()) return;
    seen = posted_.load();
    const Task task{task_invoke_.load(), task_callable_.load()};
    long expected = tagged(seen, kPosted);
    if (!state_.compare_exchange_strong(expected, tagged(seen, kClaimed)))
      continue;  // the caller took it back (or a newer task is posted: the next poll sees it)
    task();
    ++worker_ran_;
    state_.store(tagged(seen, kDone));
    if (caller_sleeping_.load()) {
      { std::lock_guard<std::mutex> lock(mutex_); }  // the caller is in its wait, or sees kDone first
      done_cv_.notify_one();
    }
  }
}

void StepLanes::runErased(Task a, Task b) {
  // The previous run has returned, so the worker reads no task now but a stale generation,
  // whose claim fails.
  task_invoke_.store(a.invoke);
  task_callable_.store(a.callable);
  const long generation = posted_.load() + 1;
  state_.store(tagged(generation, kPosted));
  posted_.store(generation);
  if (worker_sleeping_.load()) {
    { std::lock_guard<std::mutex> lock(mutex_); }
    wake_.notify_one();
  }
  b();
  long expected = tagged(generation, kPosted);
  if (state_.compare_exchange_strong(expected, tagged(generation, kClaimed))) {
    a();  // the worker had not started it: take it back
    ++caller_took_;
  } else {
    const long done = tagged(generation, kDone);
    auto finished = [&] { return state_.load() == done; };
    if (!pollFor(finished)) {
      std::unique_lock<std::mutex> lock(mutex_);
      caller_sleeping_.store(true);
      done_cv_.wait(lock, finished);
      caller_sleeping_.store(false);
    }
  }
  state_.store(tagged(generation, kIdle));
}

}  // namespace colosim
