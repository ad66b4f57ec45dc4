#pragma once
/// @file
/// A box: the most common 3D shape (crates, walls, triggers). Centred on its local origin and
/// aligned with its local axes; a Transform3 turns and places it.

#include <collide/core/aabb.hpp>
#include <collide/core/transform3.hpp>

#include <array>
#include <cstdint>

namespace collide {

/// A solid box [-half, half] in local space, optionally rounded by `radius` (every point within
/// `radius` of the core box).
///
/// Features (manifold.hpp, DESIGN.md "Feature ids"):
/// - vertex i, i in 0..7: bit k of i set means the + side on axis k (x = bit 0, y = bit 1,
///   z = bit 2), so vertex i is ((i & 1) ? +hx : -hx, (i & 2) ? +hy : -hy, (i & 4) ? +hz : -hz);
/// - edge 4 k + j, k in 0..2 the axis the edge runs along, j in 0..3: bit 0 of j is the side on
///   axis (k + 1) % 3, bit 1 the side on axis (k + 2) % 3;
/// - face 2 k + s: the face with outward normal -axis k (s = 0) or +axis k (s = 1).
struct Box {
  Vec3 half{0.0f, 0.0f, 0.0f};  ///< half extents, > 0 on every axis, world units
  float radius = 0.0f;          ///< rounding radius, >= 0

  /// Corner i (see the feature numbering), local space.
  [[nodiscard]] constexpr Vec3 vertex(int i) const noexcept {
    return {(i & 1) ? half.x : -half.x, (i & 2) ? half.y : -half.y, (i & 4) ? half.z : -half.z};
  }
};

/// A validated box. Throws InvalidInput if a half extent is not finite or <= 0, or the radius
/// is negative or not finite.
[[nodiscard]] Box make_box(Vec3 half, float radius = 0.0f);

/// Bounding box of the box (with its radius) placed by `xf`, world space: the rotated
/// extents are |R| half (Ericson, Real-Time Collision Detection, 4.2.6).
[[nodiscard]] Aabb3 compute_aabb(const Box& box, const Transform3& xf) noexcept;

}  // namespace collide
