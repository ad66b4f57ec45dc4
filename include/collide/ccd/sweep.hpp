#pragma once
/// @file
/// Motion over one step: a `Sweep` (translation and rotation, interpolated over t in [0, 1]),
/// and the swept AABB a broad phase needs to find every pair that may touch during the step.

#include <collide/core/aabb.hpp>
#include <collide/core/transform.hpp>
#include <collide/narrow/support.hpp>
#include <collide/shape/shape2d.hpp>

namespace collide {

/// A body's motion over one step, t in [0, 1]: its centre of rotation moves on a straight line
/// from `c0` to `c1` while its angle turns linearly from `a0` to `a1` (radians,
/// counter-clockwise; a1 - a0 may exceed 2 pi for fast spins). The centre of rotation is the
/// point `local_center` of the shape's local frame (usually its centre of mass). Rotating about
/// the centre of mass keeps the swept path tight, which is why the centre is stored rather than
/// the frame origin (the idea of Box2D's b2Sweep).
struct Sweep {
  Vec2 local_center{0.0f, 0.0f};  ///< centre of rotation, shape local space
  Vec2 c0{0.0f, 0.0f};            ///< world position of the centre at t = 0
  Vec2 c1{0.0f, 0.0f};            ///< world position of the centre at t = 1
  float a0 = 0.0f;                ///< angle at t = 0, radians
  float a1 = 0.0f;                ///< angle at t = 1, radians

  /// The motion that starts at `start`, moves the centre `local_center` by `translation` (world
  /// units) and turns by `rotation` (radians, counter-clockwise) over the step.
  [[nodiscard]] static Sweep from_motion(const Transform& start, Vec2 local_center,
                                         Vec2 translation, float rotation) noexcept {
    const Vec2 c = transform_point(start, local_center);
    const float a = start.q.angle();
    return {local_center, c, c + translation, a, a + rotation};
  }

  /// The shape's transform at time t (t in [0, 1]; other values extrapolate).
  [[nodiscard]] Transform at(float t) const noexcept {
    const Rot2 q = Rot2::from_angle(a0 + t * (a1 - a0));
    const Vec2 c = c0 + t * (c1 - c0);
    return {c - rotate(q, local_center), q};
  }
};

/// Throws InvalidInput naming the field if a sweep number is not finite.
void check_sweep(const Sweep& sweep, const char* name);

/// The box holding shape `shape` placed by `xf` and translated by `translation` (world units)
/// over the step, world space. Exact: under translation the box moves rigidly, so the swept box
/// is the union of the start and end boxes.
template <Shape2DType S>
[[nodiscard]] Aabb swept_aabb(const S& shape, const Transform& xf, Vec2 translation) noexcept {
  const Aabb start = compute_aabb(shape, xf);
  return merge(start, Aabb{start.min + translation, start.max + translation});
}

/// `swept_aabb` for a shape whose type is known only at run time.
[[nodiscard]] Aabb swept_aabb(const Shape2D& shape, const Transform& xf,
                              Vec2 translation) noexcept;

/// A box holding the shape at every moment of a rotating `sweep`, world space; conservative.
/// Without rotation it is exact (the union of the end boxes). With rotation, every core point
/// strays from the straight line between its end positions by at most rho * dA^2 / 8 (rho its
/// distance from the centre, dA the turn: the interpolation error bound of the arc), so the
/// union of the end boxes grown by that is conservative; it is intersected with the box of the
/// centre's path grown by the shape's reach from the centre, which wins for large turns.
[[nodiscard]] Aabb swept_aabb(const ConvexProxy& proxy, const Sweep& sweep) noexcept;

/// `swept_aabb` of a rotating sweep for any 2D shape.
template <Shape2DType S>
[[nodiscard]] Aabb swept_aabb(const S& shape, const Sweep& sweep) noexcept {
  return swept_aabb(ConvexProxy(shape), sweep);
}

/// `swept_aabb` of a rotating sweep for a shape whose type is known only at run time.
[[nodiscard]] Aabb swept_aabb(const Shape2D& shape, const Sweep& sweep) noexcept;

}  // namespace collide
