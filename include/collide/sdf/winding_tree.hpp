#pragma once
/// @file
/// The fast generalised winding number of a triangle soup (Barill, Dickson, Schmidt, Levin &
/// Jacobson, "Fast Winding Numbers for Soups and Clouds", SIGGRAPH 2018): over a hierarchy of
/// the triangles, a cluster far from the query adds the second-order expansion of its solid
/// angles about its area centroid instead of one solid angle per triangle. The hierarchy is the
/// mesh's own BVH (shape/triangle_bvh.hpp): its child boxes are tight, its nodes test four
/// children at once, and there is no second tree to build.

#include <collide/core/math.hpp>
#include <collide/shape/triangle_bvh.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace collide {

/// A cluster is taken as its expansion when the query is farther from its centre than this
/// many times its radius. Barill et al. use 2 with the second-order expansion; measured on every
/// fifth node of 64k-node grids over dungeon.obj and undulating.obj against the exact sum, 2.5
/// is the ratio at which it beats the first-order tree it replaced (2.5 radii too) on each
/// count: mean error 1.05e-3 / 3.6e-3 (was 6.8e-3 / 4.6e-3), largest 0.013 / 0.015 (was 0.054 /
/// 0.018), signs wrong under the open terrain 9 (was 28); at 2 the terrain's were 45.
inline constexpr float kWindingFarRatio = 2.5f;

/// The solid angle of triangle (a, b, c) seen from the origin, signed: positive when the origin
/// is on the side its normal (b - a) x (c - a) points away from (Van Oosterom & Strackee, "The
/// Solid Angle of a Plane Triangle", IEEE Trans. Biomed. Eng. 30(2), 1983).
[[nodiscard]] float solid_angle(Vec3 a, Vec3 b, Vec3 c) noexcept;

/// The expansions of a BVH's clusters, one per child box of each node (the coordinates of the
/// BVH: a TriangleMesh's, relative to its origin). Builds in O(n log n) for n triangles (each
/// cluster's radius is measured over its triangles); a query costs O(log n) far from the
/// surface, more near it (nearby leaves are summed exactly). Keeps a reference to `bvh`, which
/// must outlive it and stay unchanged.
class WindingTree {
 public:
  /// Builds over `bvh`'s clusters (positions finite: make_triangle_mesh validates). Allocates.
  explicit WindingTree(const TriangleBvh& bvh);
  /// Not from a temporary BVH: the tree keeps a reference to it.
  explicit WindingTree(const TriangleBvh&& bvh) = delete;
  /// Generalised winding number of `q` (the BVH's coordinates): 1 inside a closed outward-wound
  /// surface, 0 outside, in between near an open surface's holes. Far clusters add their
  /// expansion, so it approximates the exact sum of solid angles (winding_number in
  /// distance_field.hpp) closely enough to compare with 1/2.
  [[nodiscard]] float operator()(Vec3 q) const noexcept;

 private:
  /// The four children of one BVH node as lanes per number: each cluster's area centroid, its
  /// far bound (kWindingFarRatio times its radius, squared; +inf in an unused slot, which is
  /// never far, and the query skips it as TriangleBvh::used_slots says), the sum of its
  /// triangles' area-weighted normals N = sum of A_t, and the first moment
  /// M = sum of A_t (c_t - centre)^T over its triangles' centroids c_t.
  struct alignas(16) Clusters {
    std::array<std::array<float, kBvhWidth>, 3> centre;
    std::array<float, kBvhWidth> far_squared;
    std::array<std::array<float, kBvhWidth>, 3> normal;
    std::array<std::array<float, kBvhWidth>, 9> moment;  ///< row-major: M[i][j] at 3 i + j
  };
  const TriangleBvh* bvh_ = nullptr;
  std::vector<Clusters> clusters_;  ///< per BVH node
};

}  // namespace collide
