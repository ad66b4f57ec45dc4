#pragma once
/// @file
/// A capsule (a segment swept by a circle) in local space.

#include <collide/core/aabb.hpp>
#include <collide/core/transform.hpp>

namespace collide {

/// A solid capsule: every point within `radius` of the segment a-b. Local space.
struct Capsule {
  Vec2 a{0.0f, 0.0f};   ///< first end of the core segment, local space
  Vec2 b{0.0f, 0.0f};   ///< second end of the core segment, local space
  float radius = 0.0f;  ///< >= 0, world units
};

/// A validated capsule. Throws InvalidInput if a coordinate or the radius is not finite, the
/// radius is negative, or a and b coincide (use a Circle; ends about 1e-19 apart count as
/// coinciding: their squared distance underflows float).
[[nodiscard]] Capsule make_capsule(Vec2 a, Vec2 b, float radius);

/// Bounding box of the capsule placed by `xf`, world space.
[[nodiscard]] Aabb compute_aabb(const Capsule& capsule, const Transform& xf) noexcept;

}  // namespace collide
