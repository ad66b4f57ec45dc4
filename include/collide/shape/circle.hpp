#pragma once
/// @file
/// A circle in local space.

#include <collide/core/aabb.hpp>
#include <collide/core/transform.hpp>

namespace collide {

/// A solid circle: every point within `radius` of `center`. Local space.
struct Circle {
  Vec2 center{0.0f, 0.0f};  ///< local space
  float radius = 0.0f;      ///< >= 0, world units
};

/// A validated circle. Throws InvalidInput if `center` or `radius` is not finite or
/// `radius` < 0. A zero radius is allowed (a point).
[[nodiscard]] Circle make_circle(Vec2 center, float radius);

/// Bounding box of the circle placed by `xf`, world space.
[[nodiscard]] Aabb compute_aabb(const Circle& circle, const Transform& xf) noexcept;

}  // namespace collide
