#pragma once
/// @file
/// A static bounding volume hierarchy over the triangles of a mesh: the exact nearest triangle
/// to a point, and every triangle whose box overlaps a query box, without scanning all of them.

#include <collide/core/aabb.hpp>
#include <collide/walkmesh/closest_point_triangle.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace collide {

/// Most triangles in one BVH leaf.
inline constexpr int kBvhLeafTriangles = 4;
/// Candidate split planes per axis for the binned surface area heuristic.
inline constexpr int kBvhBins = 16;
/// Depth of the fixed traversal stack. A traversal holds at most one pending sibling per level,
/// so this bounds the tree depth that queries handle; SAH trees of real levels are far shallower.
/// Deeper subtrees would be skipped (never overrun): the build falls back to median splits when
/// SAH cannot split, so depth stays near log2(n).
inline constexpr int kBvhStackSize = 64;

/// The triangle nearest to a point.
struct BvhNearest {
  std::uint32_t triangle = std::numeric_limits<std::uint32_t>::max();  ///< input index; max() when empty
  TrianglePoint closest{};  ///< nearest point (BVH space) and its weights of the triangle's a, b, c
  float distance_squared = std::numeric_limits<float>::infinity();  ///< squared distance to it
};

/// Static AABB tree over triangles, built top-down by the binned surface area heuristic (Wald,
/// "On fast construction of SAH-based bounding volume hierarchies", 2007; Ericson, Real-Time
/// Collision Detection, 6.2), falling back to median splits. The tree keeps its own copy
/// of the corners in leaf order, so a query touches contiguous memory. Coordinates are those
/// given to the constructor (callers shift large worlds to a local origin first).
class TriangleBvh {
 public:
  TriangleBvh() = default;
  /// Builds over `triangles` (indices into `positions`). Indices must be in range and positions
  /// finite (callers validate; this is not an entry point for user data).
  TriangleBvh(std::span<const Vec3> positions, std::span<const glm::uvec3> triangles);

  /// The exact nearest point of all triangles to `p`: branch and bound, nearer child first,
  /// pruning boxes no nearer than the best so far (so among triangles at exactly the same
  /// distance, the first one found wins: deterministic for a given tree). No allocation.
  [[nodiscard]] BvhNearest nearest(Vec3 p) const noexcept;

  /// Calls `visit(triangle index)` for every triangle whose bounding box overlaps `box`.
  template <class Visit>
  void query(const Aabb3& box, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::array<std::uint32_t, kBvhStackSize> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!overlap(node.bounds, box)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
          if (overlap(leaf_bounds_[i], box)) visit(ids_[i]);
        }
      } else if (top + 2 <= kBvhStackSize) {
        stack[top++] = node.first;
        stack[top++] = node.first + 1;
      }
    }
  }

  [[nodiscard]] std::size_t triangle_count() const noexcept { return ids_.size(); }
  [[nodiscard]] std::size_t node_count() const noexcept { return nodes_.size(); }
  /// Box of everything; a zero box when empty.
  [[nodiscard]] Aabb3 bounds() const noexcept { return nodes_.empty() ? Aabb3{} : nodes_[0].bounds; }

 private:
  struct Node {
    Aabb3 bounds;
    std::uint32_t first = 0;  ///< leaf: first slot in ids_; inner: index of the left child
    std::uint32_t count = 0;  ///< leaf: number of triangles (> 0); inner: 0
  };
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> ids_;                 ///< input triangle index per slot
  std::vector<std::array<Vec3, 3>> corners_;       ///< corners per slot
  std::vector<Aabb3> leaf_bounds_;                 ///< box per slot
};

}  // namespace collide
