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
#include <collide/world/world2d.hpp>

#include <cstdint>
#include <span>
#include <variant>

namespace collide::detail {

class BodyBroadPhase {
 public:
  explicit BodyBroadPhase(WorldBroadPhase kind) {
    switch (kind) {
      case WorldBroadPhase::temporal: bp_.emplace<TemporalBroadPhase>(); break;
      case WorldBroadPhase::hierarchical_grid: bp_.emplace<HierarchicalGrid>(); break;
      case WorldBroadPhase::sorted_grid: bp_.emplace<SortedGrid>(); break;
      case WorldBroadPhase::loose_grid: bp_.emplace<LooseGrid>(); break;
      case WorldBroadPhase::hash_grid: bp_.emplace<HashGrid>(); break;
      case WorldBroadPhase::dynamic_tree: bp_.emplace<DynamicTree>(); break;
      case WorldBroadPhase::sweep_and_prune: bp_.emplace<SweepAndPrune>(); break;
      case WorldBroadPhase::brute_force: bp_.emplace<BruteForce>(); break;
    }
  }

  /// The boxes (and, for the temporal broad phase, speed bounds) at `time`. `same_objects`:
  /// the same proxies as last call, so incremental structures may update instead of rebuild.
  void set(std::span<const Aabb> boxes, std::span<const float> speed_bounds, double time,
           bool same_objects) {
    std::visit(
        [&](auto& bp) {
          using T = std::decay_t<decltype(bp)>;
          if constexpr (std::is_same_v<T, TemporalBroadPhase>) {
            if (same_objects && built_) {
              bp.update(boxes, time);
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

  /// Speed bounds from now on, after the collision response changed velocities (only the
  /// temporal broad phase uses them).
  void set_speed_bounds(std::span<const float> speed_bounds) {
    if (auto* t = std::get_if<TemporalBroadPhase>(&bp_); t != nullptr && built_) {
      t->set_speed_bounds(speed_bounds);
    }
  }

  /// Every overlapping pair once, (i, j) with i < j, sorted.
  void find_pairs(PairList& pairs) {
    std::visit([&](auto& bp) { bp.find_pairs(pairs); }, bp_);
    sort_pairs(pairs);
  }

  void query(const Aabb& box, QueryCallback callback) const {
    std::visit([&](const auto& bp) { bp.query(box, callback); }, bp_);
  }
  void ray_cast(const Ray& ray, RayCallback callback) const {
    std::visit([&](const auto& bp) { bp.ray_cast(ray, callback); }, bp_);
  }

  /// Pair checks the temporal broad phase skipped so far (0 for the others).
  [[nodiscard]] std::int64_t skipped_checks() const noexcept {
    const auto* t = std::get_if<TemporalBroadPhase>(&bp_);
    return t != nullptr ? t->stats().skipped_checks : 0;
  }

 private:
  std::variant<TemporalBroadPhase, HierarchicalGrid, SortedGrid, LooseGrid, HashGrid,
               DynamicTree, SweepAndPrune, BruteForce>
      bp_;
  bool built_ = false;
};

}  // namespace collide::detail
