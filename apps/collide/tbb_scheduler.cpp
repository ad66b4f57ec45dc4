#include "tbb_scheduler.hpp"

#include <collide/core/error.hpp>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <string>

namespace collide::cli {
namespace {

class TbbScheduler final : public TaskScheduler {
 public:
  // oneTBB caps its worker threads at the core count less one unless told otherwise: more
  // threads than cores (--threads 8 on 2 cores, the determinism tests) are asked for explicitly.
  explicit TbbScheduler(int threads)
      : allowed_(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads)),
        arena_(threads),
        workers_(threads) {}

  [[nodiscard]] int worker_count() const noexcept override { return workers_; }

  void parallel_for(int count, int min_range, TaskFunction task, void* context) override {
    // A thread's slot in the arena is its worker index: two ranges running at once never share
    // one (the arena has exactly workers_ slots, the calling thread in one of them).
    arena_.execute([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, count, static_cast<std::size_t>(std::max(1, min_range))),
                        [&](const tbb::blocked_range<int>& r) {
                          task(r.begin(), r.end(), tbb::this_task_arena::current_thread_index(), context);
                        });
    });
  }

 private:
  tbb::global_control allowed_;
  tbb::task_arena arena_;
  int workers_;
};

}  // namespace

std::shared_ptr<TaskScheduler> make_scheduler(int threads) {
  if (threads < 0 || threads > kMaxThreads) {
    throw InvalidInput("--threads: " + std::to_string(threads) + " (valid: 0 for every core, or 1 to " +
                       std::to_string(kMaxThreads) + ")");
  }
  if (threads == 0) threads = std::max(1, tbb::this_task_arena::max_concurrency());
  if (threads == 1) return std::make_shared<SerialScheduler>();
  return std::make_shared<TbbScheduler>(threads);
}

}  // namespace collide::cli
