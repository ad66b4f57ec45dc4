#pragma once
// The seam between collide and a game's job system. The world splits the work of a step into
// ranges of independent items (bodies, pairs) and hands them to a `TaskScheduler`; a game plugs in
// its own (as Box2D v3 takes `enqueueTask` / `finishTask` callbacks and Jolt a `JobSystem`), and
// `collide run` plugs in oneTBB. Without one the world runs every range on the calling thread.
//
// Determinism: the world never lets the split decide a result. Each item writes only its own
// output slots (or a per-worker scratch that is merged in item order afterwards), so a step is
// bit for bit the same for every worker count and every schedule.

#include <type_traits>

namespace collide {

/// Work over items [begin, end) on worker `worker` (0 <= worker < TaskScheduler::worker_count();
/// two ranges running at the same time never share a worker index). `context` is the caller's.
using TaskFunction = void (*)(int begin, int end, int worker, void* context);

/// A parallel-for provided by the game. Thread safety: `parallel_for` is called from one thread at
/// a time (the one stepping the world) and must return only when every item has run.
class TaskScheduler {
 public:
  virtual ~TaskScheduler() = default;

  /// How many workers may run ranges at once (>= 1): the world keeps this many scratch buffers.
  [[nodiscard]] virtual int worker_count() const noexcept = 0;

  /// Runs `task` over [0, count) in ranges of at least `min_range` items (the last may be
  /// shorter), in any order and on any workers, and returns when all have run. An exception
  /// thrown by `task` may be rethrown here (the world's tasks do not throw).
  virtual void parallel_for(int count, int min_range, TaskFunction task, void* context) = 0;
};

/// The scheduler of one worker: every range runs on the calling thread, in order.
class SerialScheduler final : public TaskScheduler {
 public:
  [[nodiscard]] int worker_count() const noexcept override { return 1; }
  void parallel_for(int count, int /*min_range*/, TaskFunction task, void* context) override {
    if (count > 0) task(0, count, 0, context);
  }
};

/// Runs f(begin, end, worker) over [0, count) on `scheduler`'s workers in ranges of at least
/// `min_range` items, or on the calling thread as one range (worker 0) when there is no
/// scheduler, it has one worker, or the work is a single range. `f` may be any callable; it is
/// passed to the scheduler through its `context` pointer (no allocation).
template <class F>
void parallel_for(TaskScheduler* scheduler, int count, int min_range, F&& f) {
  if (count <= 0) return;
  if (scheduler == nullptr || scheduler->worker_count() < 2 || count <= min_range) {
    f(0, count, 0);
    return;
  }
  using Fn = std::remove_reference_t<F>;
  scheduler->parallel_for(
      count, min_range,
      [](int begin, int end, int worker, void* context) { (*static_cast<Fn*>(context))(begin, end, worker); }, &f);
}

}  // namespace collide
