#pragma once
/// @file
/// Ray casts against single shapes (lasers, mouse picks, line of sight), and reflection for
/// lasers and mirrors. One fraction convention: point = origin + fraction * translation.

#include <collide/core/ray.hpp>
#include <collide/shape/shape2d.hpp>

namespace collide {

/// Where a ray first enters a shape. On a miss: hit false, every other field zero.
struct RayHit {
  bool hit = false;
  float fraction = 0.0f;     ///< along the ray's translation, [0, 1]
  Vec2 point{0.0f, 0.0f};    ///< world space, on the shape's surface
  Vec2 normal{0.0f, 0.0f};   ///< unit outward surface normal at `point`, world space
};

/// First entry of `ray` (world space) into the shape placed by `xf`. A ray that starts inside
/// the shape (or exactly on its surface heading in) reports no hit: it never enters. A ray of
/// zero length reports no hit. Circle and capsule: analytic quadratic (Ericson 5.3.2);
/// polygon: clipping the ray by each edge half-plane (Cyrus & Beck 1978; Ericson 5.3.8), and a
/// rounded polygon as the union of its offset edges and vertex circles.
template <Shape2DType S>
[[nodiscard]] RayHit raycast(const S& shape, const Transform& xf, const Ray& ray) noexcept;

/// `raycast` for a shape whose type is known only at run time.
[[nodiscard]] RayHit raycast(const Shape2D& shape, const Transform& xf, const Ray& ray) noexcept;

/// `direction` mirrored about the plane with unit normal `normal`: d - 2 (d . n) n.
[[nodiscard]] constexpr Vec2 reflect(Vec2 direction, Vec2 normal) noexcept {
  return direction - 2.0f * (direction.x * normal.x + direction.y * normal.y) * normal;
}

/// The ray that continues a laser after it hits a mirror: it starts at the hit point and keeps
/// the length the incoming ray had left, mirrored about the hit normal. `hit` must be a hit of
/// `ray`.
[[nodiscard]] constexpr Ray reflect(const Ray& ray, const RayHit& hit) noexcept {
  return Ray{hit.point, (1.0f - hit.fraction) * reflect(ray.translation, hit.normal)};
}

}  // namespace collide
