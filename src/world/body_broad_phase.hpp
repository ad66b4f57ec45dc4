#pragma once
// The world's body-body broad phase: any of collide's broad phases behind one small interface,
// so a game (or `collide run --broadphase`) can pick by name and compare. Pairs come out sorted,
// which makes the rest of the step independent of the choice.

#include <collide/broad/brute_force.hpp>
#include <collide/broad/dynamic_tree.hpp>
#include <collide/broad/hash_grid.hpp>
#include <collide/broad/hierarchical_grid.hpp>
#include <collide/broad/loose_grid.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/broad/sweep_and_prune.hpp>
#include <collide/broad/temporal_broad_phase.hpp>
#include <collide/world/world.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <variant>

namespace collide::detail {

template <int D>
class BodyBroadPhaseN {
 public:
  explicit BodyBroadPhaseN(WorldBroadPhase kind) {
    switch (kind) {
      case WorldBroadPhase::temporal: bp_.template emplace<TemporalBroadPhaseN<D>>(); break;
      case WorldBroadPhase::hierarchical_grid: bp_.template emplace<HierarchicalGridN<D>>(); break;
      case WorldBroadPhase::sorted_grid: bp_.template emplace<SortedGridN<D>>(); break;
      case WorldBroadPhase::loose_grid: bp_.template emplace<LooseGridN<D>>(); break;
      case WorldBroadPhase::hash_grid: bp_.template emplace<HashGridN<D>>(); break;
      case WorldBroadPhase::dynamic_tree: bp_.template emplace<DynamicTreeN<D>>(); break;
      case WorldBroadPhase::sweep_and_prune: bp_.template emplace<SweepAndPruneN<D>>(); break;
      case WorldBroadPhase::brute_force: bp_.template emplace<BruteForceN<D>>(); break;
    }
  }

  /// The boxes (and, for the temporal broad phase, speed bounds) at `time`. `same_objects`:
  /// the same proxies as last call, so incremental structures may update instead of rebuild.
  void set(std::span<const AabbN<D>> boxes, std::span<const float> speed_bounds, double time,
           bool same_objects, TaskScheduler* scheduler = nullptr) {
    const bool finishing = std::exchange(updating_, false);  // (reset first: finish_update may throw)
    std::visit(
        [&](auto& bp) {
          using T = std::decay_t<decltype(bp)>;
          if constexpr (std::is_same_v<T, TemporalBroadPhaseN<D>>) {
            if (finishing) {
              bp.finish_update(boxes);  // (begin_update had the same objects and time)
            } else if (same_objects && built_) {
              bp.update(boxes, time, scheduler);
            } else {
              bp.build(boxes, speed_bounds, time);
            }
          } else {
            if (same_objects && built_) {
              bp.update(boxes);
            } else {
              bp.build(boxes);
            }
          }
        },
        bp_);
    built_ = true;
  }

  /// The temporal broad phase's update in parts (TemporalBroadPhaseN::begin_update): true when
  /// it began one, for these `count` proxies at `time`; then the caller passes every proxy to
  /// update_range, in ranges on any workers, and calls set() with the same boxes and time. False
  /// (nothing begun) for the other kinds, before the first set(), and when the proxies changed.
  bool begin_update(std::size_t count, double time, bool same_objects) {
    auto* t = std::get_if<TemporalBroadPhaseN<D>>(&bp_);
    if (t == nullptr || !built_ || !same_objects) return false;
    t->begin_update(count, time);
    updating_ = true;
    return true;
  }
  /// Proxies [begin, end) of the update begun by begin_update (`boxes`: every proxy's box).
  void update_range(int begin, int end, std::span<const AabbN<D>> boxes) noexcept {
    std::get_if<TemporalBroadPhaseN<D>>(&bp_)->update_range(begin, end, boxes);
  }

  /// True when the temporal broad phase's next find_pairs, after set() to `next_time`, would
  /// rebuild its candidate set and rebuild_now may do it ahead (false for the other kinds).
  [[nodiscard]] bool rebuild_due(double next_time) const noexcept {
    const auto* t = std::get_if<TemporalBroadPhaseN<D>>(&bp_);
    return t != nullptr && built_ && t->rebuild_due(next_time);
  }
  /// The temporal broad phase's candidate set rebuilt now for the set() to `next_time`, on the
  /// calling thread (it touches nothing else: a worker may run it while the bodies move).
  void rebuild_now(double next_time) {
    if (auto* t = std::get_if<TemporalBroadPhaseN<D>>(&bp_)) t->rebuild_now(next_time);
  }

  /// Speed bounds from now on, after the collision response changed velocities (only the
  /// temporal broad phase uses them).
  void set_speed_bounds(std::span<const float> speed_bounds, TaskScheduler* scheduler = nullptr) {
    if (auto* t = std::get_if<TemporalBroadPhaseN<D>>(&bp_); t != nullptr && built_) {
      t->set_speed_bounds(speed_bounds, scheduler);
    }
  }

  /// Every overlapping pair once, (i, j) with i < j, sorted (the temporal broad phase on the
  /// scheduler's workers when there is one, and sorted already).
  void find_pairs(PairList& pairs, TaskScheduler* scheduler = nullptr) {
    std::visit(
        [&](auto& bp) {
          if constexpr (std::is_same_v<std::decay_t<decltype(bp)>, TemporalBroadPhaseN<D>>) {
            bp.find_pairs(pairs, scheduler);
          } else {
            bp.find_pairs(pairs);
            sort_pairs(pairs, sort_scratch_);
          }
        },
        bp_);
  }

  void query(const AabbN<D>& box, QueryCallback callback) const {
    std::visit([&](const auto& bp) { bp.query(box, callback); }, bp_);
  }
  void ray_cast(const RayN<D>& ray, RayCallback callback) const {
    std::visit([&](const auto& bp) { bp.ray_cast(ray, callback); }, bp_);
  }

  /// Candidate sets the temporal broad phase built so far (0 for the others).
  [[nodiscard]] std::int64_t rebuilds() const noexcept {
    const auto* t = std::get_if<TemporalBroadPhaseN<D>>(&bp_);
    return t != nullptr ? t->stats().rebuilds : 0;
  }
  /// Pair checks the temporal broad phase skipped so far (0 for the others).
  [[nodiscard]] std::int64_t skipped_checks() const noexcept {
    const auto* t = std::get_if<TemporalBroadPhaseN<D>>(&bp_);
    return t != nullptr ? t->stats().skipped_checks : 0;
  }

 private:
  std::variant<TemporalBroadPhaseN<D>, HierarchicalGridN<D>, SortedGridN<D>, LooseGridN<D>,
               HashGridN<D>, DynamicTreeN<D>, SweepAndPruneN<D>, BruteForceN<D>>
      bp_;
  PairList sort_scratch_;  ///< sort_pairs' storage, kept across frames
  bool built_ = false;
  bool updating_ = false;  // begin_update began an update that set() finishes
};

}  // namespace collide::detail
