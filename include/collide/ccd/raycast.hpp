#pragma once
/// @file
/// Ray casts against single shapes (lasers, mouse picks, line of sight), and reflection for
/// lasers and mirrors. One fraction convention: point = origin + fraction * translation.

#include <collide/core/ray.hpp>
#include <collide/shape/shape2d.hpp>

#include <cstdint>

namespace collide {

/// Where a ray first enters a shape, in D dimensions. On a miss: hit false, every other field
/// zero.
template <int D>
struct RayHitN {
  bool hit = false;
  float fraction = 0.0f;     ///< along the ray's translation, [0, 1]
  VecN<D> point{0.0f};       ///< world space, on the shape's surface
  VecN<D> normal{0.0f};      ///< unit outward surface normal at `point`, world space
  /// Which part of a shape made of parts was hit: the triangle index of a `TriangleMesh` or
  /// `HeightField`; 0 for a convex shape.
  std::uint32_t sub_shape = 0;
};

using RayHit = RayHitN<2>;   ///< 2D ray hit
using RayHit3 = RayHitN<3>;  ///< 3D ray hit

/// First entry of `ray` (world space) into the shape placed by `xf`. A ray must enter to hit:
/// one that starts in the closed shape (inside, or exactly on its surface whichever way it
/// heads) reports no hit, and so do a ray of zero length and a ray with a NaN coordinate. Shapes
/// must be valid (built by the make_* functions), `xf` finite. The ray is moved into the shape's
/// local frame first, so precision does not degrade far from the world origin.
/// - Circle: analytic quadratic (Ericson, Real-Time Collision Detection, 5.3.2), discriminant
///   from the closest approach (Haines et al., Ray Tracing Gems, ch. 7).
/// - Capsule: its flat sides as a slab, then the end disc on the side the ray meets (Ericson
///   5.3.7 in 2D).
/// - Polygon: the ray's line splits the vertices into left and right; walking
///   counter-clockwise, the edge that crosses from left to right is where the line enters (a
///   branch-free scan, one division). A rounded polygon is exactly the union of its core, its
///   edges pushed out by the radius and a disc at each vertex: the pushed-out polygon is
///   clipped by its edge half-planes (Cyrus & Beck 1978; Ericson 5.3.8), then one vertex disc
///   is tested when the entry lands beyond an edge's end.
/// - Segment: two-sided, the normal faces the ray's origin. A ray along the segment's line
///   (parallel within kParallelTolerance, on the line within kRelativeTolerance of the
///   segment's length) hits the nearer end with the normal pointing back along the ray, since
///   touching counts; one starting on the segment reports no hit.
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
/// `ray`. Rounding can put the new start a hair behind the mirror, so a laser loop should not
/// cast the reflected ray at the mirror it just left (a convex mirror cannot be hit again).
[[nodiscard]] constexpr Ray reflect(const Ray& ray, const RayHit& hit) noexcept {
  return Ray{hit.point, (1.0f - hit.fraction) * reflect(ray.translation, hit.normal)};
}

}  // namespace collide
