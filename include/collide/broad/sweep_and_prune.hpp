#pragma once
/// @file
/// Sweep and prune (sort and sweep): the boxes kept sorted by their min along one axis; a box
/// can only overlap the boxes that start before it ends on that axis. Between frames objects
/// move little, so the order barely changes and an insertion sort restores it in nearly O(n)
/// (Baraff, "Dynamic Simulation of Non-Penetrating Rigid Bodies", 1992; Cohen et al.,
/// "I-COLLIDE", 1995; Ericson, Real-Time Collision Detection, 7.5.2).
///
/// The sweep axis is the one along which box centres spread most, chosen at build. The boxes
/// are stored in sweep order, so the sweep reads memory sequentially. Good when objects spread
/// along an axis; poor when many boxes line up on the sweep axis (it does not rechoose it in
/// update).
///
/// Memory per object: its box and id in sweep order (8*D + 4 bytes).

#include <collide/broad/broad_phase.hpp>

#include <span>
#include <vector>

namespace collide {

/// Insertion-sorted sweep and prune over boxes in D dimensions.
template <int D>
class SweepAndPruneN {
 public:
  /// Sorts the boxes along the axis of largest spread. Throws InvalidInput for a non-finite
  /// box or min > max.
  void build(std::span<const AabbN<D>> boxes);
  /// Takes the moved boxes and restores the order by insertion sort; a different number of
  /// boxes rebuilds. Throws InvalidInput as build.
  void update(std::span<const AabbN<D>> boxes);

  /// Every overlapping pair once as (smaller id, larger id), in sweep order.
  void find_pairs(PairList& pairs) const;
  /// Each id whose box overlaps `box` (touching counts), once.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Each id whose box contains `point` (boundary included), once.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Boxes in sweep order within the ray's extent along the sweep axis.
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return static_cast<int>(items_.size()); }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept {
    return items_.capacity() * sizeof(Item);
  }
  /// The sweep axis (0 = x, 1 = y, 2 = z).
  [[nodiscard]] int axis() const noexcept { return axis_; }

 private:
  struct Item {
    AabbN<D> box;
    int id;
  };
  [[nodiscard]] bool before(const Item& a, const Item& b) const noexcept {
    return a.box.min[axis_] < b.box.min[axis_] ||
           (a.box.min[axis_] == b.box.min[axis_] && a.id < b.id);
  }
  void refresh_longest() noexcept;
  /// Calls visit(item) for the items whose min along the axis lies in [lo - longest, hi], in
  /// sweep order; visit returns false to stop.
  template <class Visit>
  void scan(float lo, float hi, Visit&& visit) const;

  std::vector<Item> items_;  // sorted by (box.min[axis_], id)
  int axis_ = 0;
  float longest_ = 0.0f;     // longest box along the axis: bounds how far back a query looks
};

using SweepAndPrune = SweepAndPruneN<2>;
using SweepAndPrune3 = SweepAndPruneN<3>;

}  // namespace collide
