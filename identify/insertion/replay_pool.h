// Replays of one recording on a fixed set of threads: first those a search needs now, and,
// on a thread that would otherwise wait, those it will probably need next.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "identify/insertion/replay.h"

namespace colosim {

/// Runs replays of one setup and recording on `threads` worker threads.
///
/// `run` returns the predictions of the replays a search asks for now. While some of them
/// are still running and a worker is free, it asks `guess` which replays the search will
/// probably ask for next, and starts them on the free workers. A guessed replay that the
/// next `run` asks for is taken as it is: a replay depends only on its setup, recording and
/// extensions, so it has the same bits as one started then. A guessed replay that the next
/// `run` does not ask for is cancelled. The predictions, and so every answer, never depend
/// on the guesses or on thread timing; only the wall time does.
class ReplayPool {
 public:
  /// The replays to guess, from the current run's extensions and the predictions of those
  /// done so far (nullptr: still running).
  using Guess = std::function<std::vector<OrganParams>(const std::vector<const Prediction*>& done)>;

  ReplayPool(const ReplaySetup& setup, const InsertionRecording& rec, int threads);
  ~ReplayPool();
  ReplayPool(const ReplayPool&) = delete;
  ReplayPool& operator=(const ReplayPool&) = delete;

  /// The predictions of `jobs`, in order (blocks until all are done).
  std::vector<Prediction> run(const std::vector<OrganParams>& jobs, const Guess& guess = {});

  /// Guessed replays started so far, and how many of them a run then asked for (these two
  /// depend on thread timing; nothing else does).
  int guessesStarted() const;
  int guessesUsed() const;

 private:
  struct Job;
  void work();
  void forgetCancelled();    // removes cancelled jobs from known_
  void dropQueuedGuesses();  // cancels and forgets the guesses not started

  const ReplaySetup& setup_;
  const InsertionRecording& rec_;
  const int threads_;
  mutable std::mutex mutex_;
  std::condition_variable work_cv_, done_cv_;
  std::deque<std::shared_ptr<Job>> asked_, guessed_;  // queued, not started
  std::vector<std::shared_ptr<Job>> known_;           // every job not cancelled
  int busy_ = 0;
  bool stop_ = false;
  int guesses_started_ = 0, guesses_used_ = 0;
  std::vector<std::thread> workers_;
};

}  // namespace colosim
