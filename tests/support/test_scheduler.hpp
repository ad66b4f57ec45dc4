#pragma once
// A TaskScheduler for tests: splits [0, count) into ranges of min_range items and runs them on
// `workers` std::threads, the ranges handed out from the end backwards (a schedule unlike the
// serial one), each thread with its own worker index. What the world and the broad phase
// promise (the same result for any worker count and schedule) is checked against it.

#include <collide/core/task_scheduler.hpp>

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace collide::test {

class ThreadScheduler final : public TaskScheduler {
 public:
  explicit ThreadScheduler(int workers) : workers_(std::max(1, workers)) {}
  [[nodiscard]] int worker_count() const noexcept override { return workers_; }
  void parallel_for(int count, int min_range, TaskFunction task, void* context) override {
    const int range = std::max(1, min_range);
    const int ranges = (count + range - 1) / range;
    std::atomic<int> next{ranges - 1};
    std::vector<std::thread> threads;
    for (int w = 0; w < workers_; ++w) {
      threads.emplace_back([&, w] {
        for (int r = next--; r >= 0; r = next--) task(r * range, std::min(count, (r + 1) * range), w, context);
      });
    }
    for (std::thread& t : threads) t.join();
  }

 private:
  int workers_;
};

}  // namespace collide::test
