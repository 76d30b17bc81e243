// Timing of one training iteration for the benchmarks: `warmup` untimed calls, then the
// median and minimum wall time of `iters` timed calls, in milliseconds.
#pragma once
#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

namespace df::bench {

struct Timing {
  double median_ms = 0, min_ms = 0;
};

inline Timing time_iterations(int warmup, int iters, const std::function<void()>& step) {
  using Clock = std::chrono::steady_clock;
  for (int i = 0; i < warmup; ++i) step();
  std::vector<double> ms;
  for (int i = 0; i < iters; ++i) {
    auto t0 = Clock::now();
    step();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return {ms[ms.size() / 2], ms.front()};
}

}  // namespace df::bench
