#include "identify/insertion/replay_pool.h"

#include <algorithm>

namespace colosim {

namespace {
bool sameExtensions(const OrganParams& a, const OrganParams& b) {
  return a.friction == b.friction && a.bending_EI_Nm2 == b.bending_EI_Nm2 && a.stiffening_per_m2 == b.stiffening_per_m2 &&
         a.fung_b == b.fung_b && a.relax_g1 == b.relax_g1 && a.soften_d_inf == b.soften_d_inf && a.set_ratio == b.set_ratio;
}
}  // namespace

struct ReplayPool::Job {
  OrganParams params;
  bool guessed = false;  // started by a guess and not asked for (yet)
  bool done = false;
  std::atomic<bool> cancel{false};
  Prediction prediction;
};

ReplayPool::ReplayPool(const ReplaySetup& setup, const InsertionRecording& rec, int threads)
    : setup_(setup), rec_(rec), threads_(std::max(1, threads)) {
  for (int t = 0; t < threads_; ++t) workers_.emplace_back([this] { work(); });
}

ReplayPool::~ReplayPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    asked_.clear();
    guessed_.clear();
    for (const auto& j : known_) j->cancel = true;
  }
  work_cv_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ReplayPool::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_cv_.wait(lock, [&] { return stop_ || !asked_.empty() || !guessed_.empty(); });
    if (stop_) return;
    std::shared_ptr<Job> job;
    if (!asked_.empty()) {
      job = asked_.front();
      asked_.pop_front();
    } else {
      job = guessed_.front();
      guessed_.pop_front();
      ++guesses_started_;
    }
    ++busy_;
    lock.unlock();
    Prediction p = replayInsertion(setup_, rec_, job->params, &job->cancel);
    lock.lock();
    job->prediction = std::move(p);
    job->done = true;
    --busy_;
    done_cv_.notify_all();
  }
}

int ReplayPool::guessesStarted() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return guesses_started_;
}

int ReplayPool::guessesUsed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return guesses_used_;
}

void ReplayPool::forgetCancelled() {
  known_.erase(std::remove_if(known_.begin(), known_.end(), [](const auto& j) { return j->cancel.load(); }),
               known_.end());
}

void ReplayPool::dropQueuedGuesses() {
  for (const auto& j : guessed_) j->cancel = true;
  guessed_.clear();
  forgetCancelled();
}

std::vector<Prediction> ReplayPool::run(const std::vector<OrganParams>& jobs, const Guess& guess) {
  std::unique_lock<std::mutex> lock(mutex_);
  dropQueuedGuesses();
  auto find = [&](const OrganParams& p) -> std::shared_ptr<Job> {
    for (const auto& j : known_)
      if (!j->cancel && sameExtensions(j->params, p)) return j;
    return nullptr;
  };
  std::vector<std::shared_ptr<Job>> mine;
  for (const OrganParams& p : jobs) {
    std::shared_ptr<Job> j = find(p);
    if (j && j->guessed) j->guessed = false, ++guesses_used_;
    if (!j) {
      j = std::make_shared<Job>();
      j->params = p;
      asked_.push_back(j);
      known_.push_back(j);
    }
    mine.push_back(j);
  }
  // Guesses still running that this run does not ask for will not be asked for.
  for (const auto& j : known_)
    if (j->guessed && !j->done) j->cancel = true;
  forgetCancelled();
  work_cv_.notify_all();

  for (;;) {
    std::vector<const Prediction*> done;
    bool all = true;
    for (const auto& j : mine) {
      done.push_back(j->done ? &j->prediction : nullptr);
      all = all && j->done;
    }
    if (all) break;
    if (guess && busy_ + static_cast<int>(asked_.size()) < threads_) {
      dropQueuedGuesses();
      for (const OrganParams& p : guess(done))
        if (!find(p)) {
          auto j = std::make_shared<Job>();
          j->params = p;
          j->guessed = true;
          guessed_.push_back(j);
          known_.push_back(j);
        }
      work_cv_.notify_all();
    }
    done_cv_.wait(lock);
  }
  std::vector<Prediction> out;
  out.reserve(mine.size());
  for (const auto& j : mine) out.push_back(j->prediction);
  return out;
}

}  // namespace colosim
