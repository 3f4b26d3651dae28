// Timing helpers for the benchmarks: medians over blocks, in wall time and in this
// thread's CPU time. On a shared machine the wall time of a block includes the time the
// thread waited for a core; the thread CPU time counts only what the code itself cost.
#pragma once

#include <algorithm>
#include <chrono>
#include <ctime>
#include <functional>
#include <vector>

namespace colosim {

struct BlockTiming {
  double wall_us = 0;  ///< median wall time per call [us]
  double cpu_us = 0;   ///< median thread CPU time per call [us]
};

inline double threadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/// The median of v (the upper one of an even count).
inline double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// Medians over `blocks` blocks of `reps` calls of f.
inline BlockTiming timeBlocks(int blocks, int reps, const std::function<void()>& f) {
  std::vector<double> wall, cpu;
  for (int b = 0; b < blocks; ++b) {
    const double c0 = threadCpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) f();
    const auto t1 = std::chrono::steady_clock::now();
    const double c1 = threadCpuSeconds();
    wall.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / reps);
    cpu.push_back(1e6 * (c1 - c0) / reps);
  }
  return {median(wall), median(cpu)};
}

}  // namespace colosim
