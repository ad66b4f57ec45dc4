#pragma once
/// @file
/// A static bounding volume hierarchy over the triangles of a mesh: the exact nearest triangle
/// to a point, and every triangle whose box overlaps a query box, without scanning all of them.

#include <collide/core/aabb.hpp>
#include <collide/shape/triangle.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace collide {

/// Children per BVH node: the four child boxes of a node are tested together (one SIMD
/// register per coordinate).
inline constexpr int kBvhWidth = 4;
/// Most triangles in one BVH leaf: a leaf is one packet of four triangles tested together.
inline constexpr int kBvhLeafTriangles = 4;
/// Candidate split planes per axis for the binned surface area heuristic.
inline constexpr int kBvhBins = 16;
/// Depth of the binary build below which nodes are split by the surface area heuristic; deeper
/// nodes are split at the median (halving their count), so the tree is at most
/// kBvhMaxSahDepth + 32 levels deep for any input of fewer than 2^32 triangles.
inline constexpr int kBvhMaxSahDepth = 32;
/// Entries of the fixed traversal stack: a visit leaves at most kBvhWidth - 1 siblings pending
/// per level of the (at most kBvhMaxSahDepth + 32 deep) tree, plus room for one node's children.
inline constexpr int kBvhStackSize = (kBvhWidth - 1) * (kBvhMaxSahDepth + 32) + 2 * kBvhWidth;

/// The triangle nearest to a point.
struct BvhNearest {
  std::uint32_t triangle = std::numeric_limits<std::uint32_t>::max();  ///< input index; max() when none
  TrianglePoint closest{};  ///< nearest point (BVH space) and its weights of the triangle's a, b, c
  float distance_squared = std::numeric_limits<float>::infinity();  ///< squared distance to it
};

/// Static AABB tree over triangles: built top-down by the binned surface area heuristic (Wald,
/// "On fast construction of SAH-based bounding volume hierarchies", 2007; Ericson, Real-Time
/// Collision Detection, 6.2) as a binary tree with leaves of at most four triangles, then
/// collapsed to four children per node by opening the largest inner child until a node has four
/// (Wald, Benthin, Boulos, "Getting rid of packets", 2008; Embree's BVH4). Boxes are stored per
/// node as four lanes per coordinate, triangles per leaf as a packet of four with their corners
/// inline, so a query tests four boxes or four triangles at once on contiguous memory.
/// Coordinates are those given to the constructor (callers shift large worlds to a local origin).
class TriangleBvh {
 public:
  TriangleBvh() = default;
  /// Builds over `triangles` (indices into `positions`). Indices must be in range and positions
  /// finite (callers validate; this is not an entry point for user data).
  TriangleBvh(std::span<const Vec3> positions, std::span<const glm::uvec3> triangles);

  /// The exact nearest point of all triangles to `p`: branch and bound, nearer child first,
  /// pruning boxes no nearer than the best so far (so among triangles at exactly the same
  /// distance, the first one found wins: deterministic for a given tree). No allocation.
  /// Only triangles within `max_distance_squared` of `p` (inclusive) count: a finite bound
  /// prunes from the first node on, for callers that know `p` is near the mesh (Detour's
  /// findNearestPoly takes a search box for the same reason). `distance_squared` of the result
  /// is recomputed from its closest point, so it may exceed the bound by rounding.
  /// Empty (triangle == max()) when no triangle is within the bound, when the tree is empty, or
  /// when squared distances from `p` overflow float (|p| beyond about 1e18).
  [[nodiscard]] BvhNearest nearest(Vec3 p, float max_distance_squared = std::numeric_limits<float>::infinity()) const noexcept;

  /// Calls `visit(triangle index)` for every triangle whose bounding box overlaps `box`.
  template <class Visit>
  void query(const Aabb3& box, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::array<std::uint32_t, kBvhStackSize> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      for (int k = 0; k < kBvhWidth; ++k) {
        // Empty slots have min = +inf, max = -inf: they overlap nothing.
        if (!(node.min_x[k] <= box.max.x && box.min.x <= node.max_x[k] && node.min_y[k] <= box.max.y &&
              box.min.y <= node.max_y[k] && node.min_z[k] <= box.max.z && box.min.z <= node.max_z[k])) {
          continue;
        }
        if (node.count[k] == 0) {
          stack[top++] = node.child[k];
          continue;
        }
        const Packet& packet = packets_[node.child[k] & ~kLeaf];
        for (std::uint32_t i = 0; i < node.count[k]; ++i) {
          const Vec3 a = packet.corner(0, i), b = packet.corner(1, i), c = packet.corner(2, i);
          if (overlap(Aabb3{glm::min(glm::min(a, b), c), glm::max(glm::max(a, b), c)}, box)) visit(packet.id[i]);
        }
      }
    }
  }

  [[nodiscard]] std::size_t triangle_count() const noexcept { return triangle_count_; }
  /// Nodes of the four-wide tree.
  [[nodiscard]] std::size_t node_count() const noexcept { return nodes_.size(); }
  /// Box of everything; a zero box when empty.
  [[nodiscard]] Aabb3 bounds() const noexcept { return bounds_; }

 private:
  /// Set in a child reference that names a leaf packet rather than a node.
  static constexpr std::uint32_t kLeaf = 0x80000000u;

  /// Four child boxes as lanes per coordinate (one cache line pair). An unused slot has
  /// min = +inf and max = -inf: infinitely far, overlapping nothing.
  struct alignas(64) Node {
    std::array<float, kBvhWidth> min_x, min_y, min_z, max_x, max_y, max_z;
    std::array<std::uint32_t, kBvhWidth> child;  ///< inner: node index; leaf: packet index | kLeaf
    std::array<std::uint32_t, kBvhWidth> count;  ///< leaf: triangles in its packet (1..4); else 0
  };
  /// Up to four triangles of one leaf, corners as lanes per coordinate. Unused lanes repeat the
  /// last triangle (same id), so they tie with it and never win a strict comparison.
  struct alignas(16) Packet {
    std::array<std::array<std::array<float, kBvhLeafTriangles>, 3>, 3> corners;  ///< [corner][axis][lane]
    std::array<std::uint32_t, kBvhLeafTriangles> id;  ///< input triangle index per lane
    [[nodiscard]] Vec3 corner(int c, std::uint32_t lane) const noexcept {
      return {corners[c][0][lane], corners[c][1][lane], corners[c][2][lane]};
    }
  };

  std::vector<Node> nodes_;      ///< root first
  std::vector<Packet> packets_;  ///< in traversal order of the build
  std::size_t triangle_count_ = 0;
  Aabb3 bounds_{};
};

}  // namespace collide
