#pragma once
/// @file
/// The fast generalised winding number of a triangle soup (Barill, Dickson, Schmidt, Levin &
/// Jacobson, "Fast Winding Numbers for Soups and Clouds", SIGGRAPH 2018): a tree over the
/// triangles whose nodes keep the sum of their area-weighted normals at their area centroid, so
/// a far cluster adds one dipole term instead of a solid angle per triangle.

#include <collide/core/math.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace collide {

/// A cluster is taken as one dipole when the query is farther from its centre than this many
/// times its radius (Barill et al. use 2 with a second-order expansion; the first-order one
/// kept here needs the cluster a little farther for the same error).
inline constexpr float kWindingFarRatio = 2.5f;
/// Most triangles in a leaf of the tree (summed exactly).
inline constexpr std::uint32_t kWindingLeafTriangles = 8;

/// The solid angle of triangle (a, b, c) seen from the origin, signed: positive when the origin
/// is on the side its normal (b - a) x (c - a) points away from (Van Oosterom & Strackee, "The
/// Solid Angle of a Plane Triangle", IEEE Trans. Biomed. Eng. 30(2), 1983).
[[nodiscard]] float solid_angle(Vec3 a, Vec3 b, Vec3 c) noexcept;

/// Tree of dipoles over a triangle soup (coordinates as given: callers pass local ones, e.g. a
/// TriangleMesh's `vertices`, relative to its origin). Builds in O(n log n) for n triangles;
/// a query costs O(log n) far from the surface, more near it (leaves are summed exactly).
class WindingTree {
 public:
  /// Builds over `triangles` (indices into `vertices`, in range; positions finite: callers
  /// validate, as make_triangle_mesh does). Allocates.
  WindingTree(std::span<const Vec3> vertices, std::span<const glm::uvec3> triangles);
  /// Generalised winding number of `q` (the tree's coordinates): 1 inside a closed
  /// outward-wound surface, 0 outside, in between near an open surface's holes. Far clusters
  /// add one dipole term each, so it approximates the exact sum of solid angles
  /// (winding_number in distance_field.hpp) closely enough to compare with 1/2.
  [[nodiscard]] float operator()(Vec3 q) const noexcept;

 private:
  struct Node {
    Vec3 centre{0.0f};      ///< area centroid of the cluster
    float radius = 0.0f;    ///< farthest corner from the centre
    Vec3 normal{0.0f};      ///< sum of area-weighted normals (half cross products)
    std::uint32_t first = 0;  ///< leaf: index into `leaves_`; inner: index of the right child
    std::uint32_t count = 0;  ///< leaf: triangles; inner: 0 (the left child follows the node)
  };
  /// A triangle as the build reads it at every level.
  struct BuildTriangle {
    std::array<Vec3, 3> corners;
    Vec3 centroid;
    Vec3 half_cross;  ///< area-weighted normal
    float area;
  };
  /// Builds the node of `cluster` (and its subtree), reordering it; returns the node's index.
  std::uint32_t build(std::span<BuildTriangle> cluster);

  /// A leaf's triangles as lanes per coordinate (a0.x, a0.y, a0.z, b0.x, ... c.z), so the
  /// solid angles of a leaf are computed side by side.
  struct Leaf {
    std::array<std::array<float, kWindingLeafTriangles>, 9> corners{};
  };
  /// Sum of the solid angles of a leaf's triangles seen from `q` (unused lanes add 0).
  [[nodiscard]] static float leaf_solid_angle(const Leaf& leaf, Vec3 q) noexcept;

  std::vector<Node> nodes_;
  std::vector<Leaf> leaves_;
};

}  // namespace collide
