#pragma once
/// @file
/// An incremental AABB tree with fattened leaves: the dynamic bounding volume hierarchy of
/// Box2D and Bullet, written for collide.
///
/// Each object's leaf holds its box grown by a margin. When the object moves, nothing happens
/// while its box stays inside the fat box; otherwise the leaf is removed and inserted again.
/// Insertion walks down to the sibling that increases the total surface metric least
/// (Goldsmith & Salmon, "Automatic Creation of Object Hierarchies for Ray Tracing", 1987), and
/// every node on the way back up is refitted and, if that lowers the surface metric, rotated:
/// a grandchild swapped with its uncle (Kopta et al., "Fast, Effective BVH Updates for Animated
/// Scenes", I3D 2012). Nodes live in one array with a free list: no allocation per node.
///
/// Memory per object: two nodes (a leaf and an internal node, each a box plus 5 ints: 36 bytes
/// in 2D, 44 in 3D), the tight box and a leaf index.

#include <collide/broad/broad_phase.hpp>
#include <collide/core/large_pages.hpp>

#include <span>
#include <utility>
#include <vector>

namespace collide {

/// Incremental AABB tree over boxes in D dimensions.
template <int D>
class DynamicTreeN {
 public:
  /// What the constructor takes; it rejects bad values, naming the field.
  struct Options {
    /// The fat box is the box grown on every side by margin + margin_fraction * its largest
    /// side: a larger margin means fewer reinsertions but looser pair tests. World units, >= 0.
    float margin = 0.0f;
    /// Growth on every side as a fraction of the box's largest side (unitless, >= 0): it scales
    /// with the object. 0.25 by default.
    float margin_fraction = 0.25f;
  };

  DynamicTreeN() = default;
  /// Throws InvalidInput for a negative or non-finite margin or margin_fraction, naming it.
  explicit DynamicTreeN(Options options);

  /// Builds the tree by inserting the boxes in id order. Throws InvalidInput for a non-finite
  /// box or min > max.
  void build(std::span<const AabbN<D>> boxes);
  /// Moves the objects to their new boxes, reinserting only those that left their fat box. A
  /// different number of boxes rebuilds. Throws InvalidInput as build.
  void update(std::span<const AabbN<D>> boxes);
  /// Adds one object (id: the number of objects before it) without touching the others: a
  /// leaf inserted as by build, O(log n) on a balanced tree (spawning objects one by one, each
  /// checked against those already placed). Throws InvalidInput as build.
  int insert(const AabbN<D>& box);

  /// Every overlapping pair once as (smaller id, larger id), by traversing the tree against
  /// itself (fat boxes prune, tight boxes decide); order: depth first, deterministic.
  void find_pairs(PairList& pairs);
  /// Each id whose box overlaps `box` (touching counts), once.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Each id whose box contains `point` (boundary included), once.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Nodes whose fat box the (clipped) ray meets are opened; leaves are tested with the tight
  /// box.
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return static_cast<int>(tight_.size()); }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;
  /// Height of the tree (a leaf alone: 0); -1 when empty.
  [[nodiscard]] int height() const noexcept { return root_ < 0 ? -1 : nodes_[root_].height; }
  /// Objects reinserted by the last update (moved out of their fat box).
  [[nodiscard]] int reinserted_count() const noexcept { return reinserted_; }

 private:
  struct Node {
    AabbN<D> box;     // fat box of a leaf; union of the children's boxes otherwise
    int parent = -1;
    int child1 = -1;  // -1 for a leaf
    int child2 = -1;
    int height = 0;   // leaf 0
    int object = -1;  // leaf: object id; free node: next free node
  };

  [[nodiscard]] AabbN<D> fat_box(const AabbN<D>& box) const noexcept;
  int allocate_node();
  void free_node(int node) noexcept;
  void insert_leaf(int leaf);
  void remove_leaf(int leaf);
  void refit_upwards(int node);
  void rotate(int node);
  template <class Overlaps, class Visit>
  void traverse(Overlaps&& overlaps, Visit&& visit) const;

  Options options_{};
  // A spawn inserts objects one at a time up to millions: the per-node and per-object arrays
  // grow on large pages once big (in a 1e6-body spawn, 23% of the page faults were the nodes').
  LargePageVector<Node> nodes_;
  int root_ = -1;
  int free_list_ = -1;
  LargePageVector<AabbN<D>> tight_;  // current box of each object
  LargePageVector<int> leaf_;        // leaf node of each object
  std::vector<std::pair<int, int>> pair_stack_;  // find_pairs traversal, kept for reuse
  int reinserted_ = 0;
};

using DynamicTree = DynamicTreeN<2>;
using DynamicTree3 = DynamicTreeN<3>;

}  // namespace collide
