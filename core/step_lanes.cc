#include "core/step_lanes.h"

namespace colosim {

namespace {
enum : long { kIdle = 0, kPosted = 1, kClaimed = 2, kDone = 3 };
inline long tagged(long generation, long phase) { return 4 * generation + phase; }
}  // namespace

StepLanes::StepLanes() : worker_([this] { loop(); }) {}

StepLanes::~StepLanes() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  worker_.join();
}

void StepLanes::loop() {
  long seen = 0;
  for (;;) {
    Task task;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || posted_ != seen; });
      if (stop_) return;
      seen = posted_;
      task = task_;
    }
    long expected = tagged(seen, kPosted);
    if (!state_.compare_exchange_strong(expected, tagged(seen, kClaimed), std::memory_order_acq_rel))
      continue;  // the caller took it back (or a newer task is posted: the wait sees it)
    task();
    ++worker_ran_;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      state_.store(tagged(seen, kDone), std::memory_order_release);
    }
    done_cv_.notify_one();
  }
}

void StepLanes::runErased(Task a, Task b) {
  long generation;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    task_ = a;
    generation = ++posted_;
    state_.store(tagged(generation, kPosted), std::memory_order_release);
  }
  wake_.notify_one();
  b();
  long expected = tagged(generation, kPosted);
  if (state_.compare_exchange_strong(expected, tagged(generation, kClaimed), std::memory_order_acq_rel)) {
    a();  // the worker had not started it: take it back
    ++caller_took_;
  } else {
    // Claimed by the worker: a short spin (the tasks take tens of microseconds), then sleep.
    const long done = tagged(generation, kDone);
    for (int spin = 0; spin < 2000 && state_.load(std::memory_order_acquire) != done; ++spin) {
    }
    if (state_.load(std::memory_order_acquire) != done) {
      std::unique_lock<std::mutex> lock(mutex_);
      done_cv_.wait(lock, [&] { return state_.load(std::memory_order_acquire) == done; });
    }
  }
  state_.store(tagged(generation, kIdle), std::memory_order_release);
}

}  // namespace colosim
