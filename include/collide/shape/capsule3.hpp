#pragma once
/// @file
/// A 3D capsule (a segment swept by a sphere) in local space: the player shape of most games.

#include <collide/core/aabb.hpp>
#include <collide/core/transform3.hpp>

namespace collide {

/// A solid capsule: every point within `radius` of the segment a-b. Local space. Features: vertex
/// 0 (end a), vertex 1 (end b), edge 0 (the side of the segment).
struct Capsule3 {
  Vec3 a{0.0f, 0.0f, 0.0f};  ///< first end of the core segment, local space
  Vec3 b{0.0f, 0.0f, 0.0f};  ///< second end of the core segment, local space
  float radius = 0.0f;       ///< >= 0, world units
};

/// A validated capsule. Throws InvalidInput if a coordinate or the radius is not finite, the
/// radius is negative, or a and b coincide (use a Sphere; ends about 1e-19 apart count as
/// coinciding: their squared distance underflows float).
[[nodiscard]] Capsule3 make_capsule(Vec3 a, Vec3 b, float radius);

/// Bounding box of the capsule placed by `xf`, world space.
[[nodiscard]] Aabb3 compute_aabb(const Capsule3& capsule, const Transform3& xf) noexcept;

}  // namespace collide
