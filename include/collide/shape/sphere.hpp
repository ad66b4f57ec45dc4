#pragma once
/// @file
/// A sphere in local space: the 3D circle.

#include <collide/core/aabb.hpp>
#include <collide/core/transform3.hpp>

namespace collide {

/// A solid sphere: every point within `radius` of `center`. Local space. Its one feature is
/// face 0.
struct Sphere {
  Vec3 center{0.0f, 0.0f, 0.0f};  ///< local space
  float radius = 0.0f;            ///< >= 0, world units
};

/// A validated sphere. Throws InvalidInput if `center` or `radius` is not finite or `radius` <
/// 0. A zero radius is allowed (a point).
[[nodiscard]] Sphere make_sphere(Vec3 center, float radius);

/// Bounding box of the sphere placed by `xf`, world space.
[[nodiscard]] Aabb3 compute_aabb(const Sphere& sphere, const Transform3& xf) noexcept;

}  // namespace collide
