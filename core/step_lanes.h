// Two lanes for the independent halves of a world step (issue 18, "both cores"): within a
// step the wall query and the self-collision query read the same state and write
// different outputs, and so do the colon and the scope solves (each holds the other's
// contact forces over the step). StepLanes runs two such tasks at once, one on a worker
// thread it owns and one on the caller's thread.
//
// Determinism: each task computes the same bits whichever thread runs it and whenever,
// since the two touch disjoint data; run() returns only when both are done. Whoever is
// free first takes the worker's task: if the worker has not started it by the time the
// caller has finished its own (the other core busy elsewhere), the caller runs it too, so
// a busy machine costs at worst the sequential time plus one atomic exchange. Each side
// polls for a short while (200 us) before it sleeps, so back-to-back steps hand their
// halves over without waking a thread.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <type_traits>

namespace colosim {

/// Waits until another thread sets `flag` (polling, then yielding the core). Only for
/// flags that a running task sets soon: the world step's lanes (core/world.cc).
void waitUntilSet(const std::atomic<bool>& flag);

class StepLanes {
 public:
  StepLanes();
  ~StepLanes();
  StepLanes(const StepLanes&) = delete;
  StepLanes& operator=(const StepLanes&) = delete;

  /// Runs a() and b(), possibly at the same time; returns when both have finished. a and
  /// b must not touch the same data (beyond reading). Not reentrant: one run() at a time.
  /// Allocation-free: the callables are passed by address, not wrapped in std::function.
  template <class A, class B>
  void run(A&& a, B&& b) {
    runErased({&call<std::remove_reference_t<A>>, &a}, {&call<std::remove_reference_t<B>>, &b});
  }

  /// How many tasks the worker thread ran, and how many the caller took back (diagnostics).
  long workerRan() const { return worker_ran_.load(); }
  long callerTookBack() const { return caller_took_.load(); }

 private:
  struct Task {
    void (*invoke)(void*) = nullptr;
    void* callable = nullptr;
    void operator()() const { invoke(callable); }
  };
  template <class F>
  static void call(void* f) {
    (*static_cast<F*>(f))();
  }
  void runErased(Task a, Task b);
  void loop();

  std::mutex mutex_;  // only for sleeping and waking
  std::condition_variable wake_, done_cv_;
  // The posted task, published before its generation.
  std::atomic<void (*)(void*)> task_invoke_{nullptr};
  std::atomic<void*> task_callable_{nullptr};
  std::atomic<long> posted_{0};  // generation of the last posted task
  // generation * 4 + phase (0 idle, 1 posted, 2 claimed, 3 done): a claim names the
  // generation it claims, so a worker waking late never runs a task already taken back.
  std::atomic<long> state_{0};
  std::atomic<bool> stop_{false}, worker_sleeping_{false}, caller_sleeping_{false};
  std::atomic<long> worker_ran_{0}, caller_took_{0};
  std::thread worker_;
};

}  // namespace colosim
