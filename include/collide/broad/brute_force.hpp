#pragma once
/// @file
/// The reference broad phase: every pair tested, O(n^2). Every other broad phase is checked
/// against it (as Jolt keeps BroadPhaseBruteForce). Fine up to a few hundred boxes.

#include <collide/broad/broad_phase.hpp>

#include <span>
#include <vector>

namespace collide {

/// All-pairs broad phase. Pairs come in (i, j) lexicographic order. Memory: one box per object.
template <int D>
class BruteForceN {
 public:
  /// Copies the boxes. Throws InvalidInput for a non-finite box or min > max (names the index).
  void build(std::span<const AabbN<D>> boxes);
  /// Same as build: nothing to reuse.
  void update(std::span<const AabbN<D>> boxes) { build(boxes); }
  /// Every overlapping pair (touching counts), i < j, lexicographic.
  void find_pairs(PairList& pairs) const;
  /// Ids whose box overlaps `box`, ascending.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Ids whose box contains `point`, ascending.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Ids whose box the ray meets, ascending, honouring clipping by the callback.
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return static_cast<int>(boxes_.size()); }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept {
    return boxes_.capacity() * sizeof(AabbN<D>);
  }

 private:
  std::vector<AabbN<D>> boxes_;
};

using BruteForce = BruteForceN<2>;
using BruteForce3 = BruteForceN<3>;

}  // namespace collide
