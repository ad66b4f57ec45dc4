#pragma once
// `collide run`'s job system: the world's TaskScheduler on oneTBB (Debian's libtbb-dev), in a
// task arena of the requested number of threads.

#include <collide/core/task_scheduler.hpp>

#include <memory>

namespace collide::cli {

/// A TaskScheduler running ranges on `threads` threads (0: every core, as oneTBB counts them;
/// the calling thread is one of them). One thread runs every range inline, without oneTBB.
/// Throws InvalidInput for a negative count or one above kMaxThreads.
[[nodiscard]] std::shared_ptr<TaskScheduler> make_scheduler(int threads);

/// Most threads --threads takes.
inline constexpr int kMaxThreads = 256;

}  // namespace collide::cli
