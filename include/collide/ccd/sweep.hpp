#pragma once
/// @file
/// Motion over one step: a `Sweep` in 2D, a `Sweep3` in 3D (translation and rotation,
/// interpolated over t in [0, 1]), and the swept AABB a broad phase needs to find every pair
/// that may touch during the step.

#include <collide/core/aabb.hpp>
#include <collide/core/transform.hpp>
#include <collide/core/transform3.hpp>
#include <collide/narrow/support.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/shape3d.hpp>

#include <cmath>

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

// ---- 3D --------------------------------------------------------------------------------------

/// A body's 3D motion over one step, t in [0, 1]: its centre of rotation (`local_center`, a
/// point of the shape's local frame, usually its centre of mass) moves on a straight line from
/// `c0` to `c1` while the body turns at constant angular velocity, from orientation `q0` by the
/// rotation vector `rotation` (world frame: the unit axis times the angle turned over the step,
/// radians, right-handed). At time t the orientation is exp(t rotation) q0.
///
/// Why a rotation vector and not an end orientation q1 with slerp: a game integrates angular
/// velocity w over a step dt, and w dt exceeds pi for fast spinners (a propeller, a thrown
/// crate); the end orientation alone cannot tell a turn of 3 pi from one of pi, and slerp takes
/// the shorter arc, so the swept path would miss most of the motion. The rotation vector holds
/// any number of turns, and the body then turns about a fixed axis at a constant rate, the
/// motion that the time of impact's bounds assume (the 3D b2Sweep would need q1 and a turn
/// count). `from_transforms` builds the shorter-arc sweep between two poses when that is what
/// the caller has.
struct Sweep3 {
  Vec3 local_center{0.0f, 0.0f, 0.0f};  ///< centre of rotation, shape local space
  Vec3 c0{0.0f, 0.0f, 0.0f};            ///< world position of the centre at t = 0
  Vec3 c1{0.0f, 0.0f, 0.0f};            ///< world position of the centre at t = 1
  Quat q0{1.0f, 0.0f, 0.0f, 0.0f};      ///< orientation at t = 0, unit quaternion
  /// Rotation over the step, world frame: axis times radians (angular velocity times dt); its
  /// length may exceed pi (several turns). Zero: no rotation.
  Vec3 rotation{0.0f, 0.0f, 0.0f};

  /// The motion that starts at `start`, moves the centre `local_center` by `translation`
  /// (world units) and turns by the rotation vector `rotation` (world frame, radians) over the
  /// step: with a body's velocities, translation = v dt and rotation = w dt.
  [[nodiscard]] static Sweep3 from_motion(const Transform3& start, Vec3 local_center,
                                          Vec3 translation, Vec3 rotation) noexcept {
    const Vec3 c = transform_point(start, local_center);
    return {local_center, c, c + translation, start.q, rotation};
  }

  /// The motion from pose `start` to pose `end` (unit quaternions), turning along the shorter
  /// arc (at most pi radians) about `local_center`.
  [[nodiscard]] static Sweep3 from_transforms(const Transform3& start, const Transform3& end,
                                              Vec3 local_center) noexcept {
    Quat d = end.q * glm::conjugate(start.q);  // the turn, world frame
    if (d.w < 0.0f) d = -d;                     // the shorter arc
    const Vec3 v{d.x, d.y, d.z};
    const float s = length(v);
    // angle = 2 atan2(|v|, w); the axis is v / |v| (any, when there is no turn).
    const Vec3 rotation = s > 0.0f ? (2.0f * std::atan2(s, d.w) / s) * v : Vec3(0.0f);
    return {local_center, transform_point(start, local_center), transform_point(end, local_center),
            start.q, rotation};
  }

  /// The orientation at time t: the turn by t * rotation applied to q0.
  [[nodiscard]] Quat orientation(float t) const noexcept {
    const float turn = length(rotation);
    if (!(turn > 0.0f)) return q0;
    const float half = 0.5f * t * turn;
    const Vec3 v = (std::sin(half) / turn) * rotation;
    return Quat{std::cos(half), v.x, v.y, v.z} * q0;
  }

  /// The shape's transform at time t (t in [0, 1]; other values extrapolate).
  [[nodiscard]] Transform3 at(float t) const noexcept {
    const Quat q = orientation(t);
    const Vec3 c = c0 + t * (c1 - c0);
    return {c - rotate(q, local_center), q};
  }
};

/// Throws InvalidInput naming the field ("<name> q0: ...") if a sweep number is not finite or
/// q0 is not a unit quaternion (within 1e-3, as `is_valid(Transform3)`).
void check_sweep(const Sweep3& sweep, const char* name);

/// The box holding 3D shape `shape` placed by `xf` and translated by `translation` (world
/// units) over the step, world space. Exact: the union of the start and end boxes.
template <Shape3DType S>
[[nodiscard]] Aabb3 swept_aabb(const S& shape, const Transform3& xf, Vec3 translation) noexcept {
  const Aabb3 start = compute_aabb(shape, xf);
  return merge(start, Aabb3{start.min + translation, start.max + translation});
}

/// `swept_aabb` of a translation for a 3D shape whose type is known only at run time.
[[nodiscard]] Aabb3 swept_aabb(const Shape3D& shape, const Transform3& xf,
                               Vec3 translation) noexcept;

/// A box holding the shape at every moment of a rotating 3D `sweep`, world space;
/// conservative, by the bounds of the 2D `swept_aabb`: exact without rotation (the union of the
/// end boxes); with a turn of dA = |rotation| radians, the union of the end boxes grown by
/// rho dA^2 / 8 (rho: the core's reach from the centre of rotation; every core point's
/// position, a circular arc about the moving centre, has second derivative at most rho dA^2,
/// so it strays from the linear interpolation of its ends by at most an eighth of that),
/// intersected with the centre's path grown by rho; then grown by the radius.
[[nodiscard]] Aabb3 swept_aabb(const ConvexProxy3& proxy, const Sweep3& sweep) noexcept;

/// `swept_aabb` of a rotating sweep for any convex 3D shape.
template <Shape3DType S>
[[nodiscard]] Aabb3 swept_aabb(const S& shape, const Sweep3& sweep) noexcept {
  return swept_aabb(ConvexProxy3(shape), sweep);
}

/// `swept_aabb` of a rotating sweep for a 3D shape whose type is known only at run time.
[[nodiscard]] Aabb3 swept_aabb(const Shape3D& shape, const Sweep3& sweep) noexcept;

}  // namespace collide
