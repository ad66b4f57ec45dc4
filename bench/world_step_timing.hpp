#pragma once
// A world step timed the same way by bench_world_scale (World2D beside Box2D v3) and
// bench_world_scale3d (World3D beside Jolt): warm-up frames untimed, then one step per
// benchmark iteration, and the counters both benches' ratio script (world_scale_ratios.py)
// reads: ns per body per frame, with and without the world's independent check, per phase,
// and the pair and continuous-collision work per body per frame.

#include <collide/core/task_scheduler.hpp>
#include <collide/world/world.hpp>

#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

namespace collide::bench {

/// Nanoseconds per body per frame of `seconds` over `frames` frames of `bodies` bodies (0 when
/// either count is 0).
inline double ns_per(double seconds, double frames, double bodies) {
  return frames > 0 && bodies > 0 ? seconds * 1e9 / (frames * bodies) : 0.0;
}

/// Steps `world` by `dt` seconds `warmup_frames` times untimed (broad phases, caches and
/// contacts settle), then once per iteration of `state`, timed on the steady clock; sets the
/// counters (`workers`: the scheduler's worker count, 1 without one) and, when the world's check
/// found a tunnelled or escaped body, a label saying so.
template <int D>
void time_world_steps(benchmark::State& state, WorldN<D>& world, const TaskScheduler* scheduler, int warmup_frames,
                      float dt) {
  for (int f = 0; f < warmup_frames; ++f) world.step(dt);
  StepStats sum;
  double seconds = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step(dt);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sum.accumulate(world.last_step_stats());
  }
  const double frames = static_cast<double>(state.iterations());
  const double bodies = world.body_count();
  state.counters["bodies"] = bodies;
  state.counters["workers"] = scheduler != nullptr ? scheduler->worker_count() : 1;
  state.counters["ns_body"] = ns_per(seconds, frames, bodies);
  state.counters["ns_body_nocheck"] = ns_per(seconds - sum.time_check, frames, bodies);
  state.counters["integrate"] = ns_per(sum.time_integrate, frames, bodies);
  state.counters["statics"] = ns_per(sum.time_statics, frames, bodies);
  state.counters["broad"] = ns_per(sum.time_broad, frames, bodies);
  state.counters["pairs"] = ns_per(sum.time_bodies, frames, bodies);
  state.counters["events"] = ns_per(sum.time_events, frames, bodies);
  state.counters["check"] = ns_per(sum.time_check, frames, bodies);
  const double per_body_frame = frames * bodies > 0 ? 1.0 / (frames * bodies) : 0.0;
  state.counters["contacts"] = static_cast<double>(sum.contacts) * per_body_frame;
  state.counters["narrow_tests"] = static_cast<double>(sum.narrow_tests) * per_body_frame;
  state.counters["ccd_bodies"] = static_cast<double>(sum.ccd_bodies) * per_body_frame;
  state.counters["toi_queries"] = static_cast<double>(sum.toi_queries) * per_body_frame;
  if (sum.tunnelled + sum.escaped > 0) {
    state.SetLabel("check: " + std::to_string(sum.tunnelled) + " tunnelled, " + std::to_string(sum.escaped) +
                   " escaped");
  }
}

}  // namespace collide::bench
