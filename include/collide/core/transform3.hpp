#pragma once
/// @file
/// 3D rigid transforms: a position and a unit quaternion (glm), world = p + q * local. The 3D
/// counterpart of `Transform`; a struct of its own because the rotation has another
/// representation (DESIGN.md, "Two dimensions, one pattern").
///
/// Inner loops (GJK, SAT, clipping) do not rotate by the quaternion point by point: they take
/// the matrix form `Frame3` once per query (a 3x3 rotation matrix and a position: 9 multiplies
/// per rotated vector instead of about 18).

#include <collide/core/aabb.hpp>
#include <collide/core/math.hpp>
#include <collide/core/transform.hpp>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include <cmath>
#include <type_traits>

namespace collide {

/// A rotation in 3D: a unit quaternion (w, x, y, z). glm's constructor order is (w, x, y, z).
using Quat = glm::quat;
/// A 3x3 matrix, column-major (glm): m[c] is column c.
using Mat3 = glm::mat3;

/// A 3D rigid transform: world = p + q * local. Default is the identity.
struct Transform3 {
  Vec3 p{0.0f, 0.0f, 0.0f};        ///< translation, world units
  Quat q{1.0f, 0.0f, 0.0f, 0.0f};  ///< rotation, unit quaternion (w, x, y, z)

  /// The transform that rotates by `rotation` (unit quaternion) and then moves to `position`.
  [[nodiscard]] static Transform3 from(Vec3 position, Quat rotation) noexcept {
    return {position, rotation};
  }
  /// The transform that rotates by `radians` about the unit `axis` (right-handed: counter-
  /// clockwise looking down the axis towards the origin) and then moves to `position`.
  [[nodiscard]] static Transform3 from_axis_angle(Vec3 position, Vec3 axis, float radians) noexcept {
    const float h = 0.5f * radians;
    const float s = std::sin(h);
    return {position, Quat{std::cos(h), s * axis.x, s * axis.y, s * axis.z}};
  }
};

/// `v` rotated by the unit quaternion `q`.
[[nodiscard]] inline Vec3 rotate(const Quat& q, Vec3 v) noexcept { return q * v; }
/// `v` rotated by the inverse of the unit quaternion `q`.
[[nodiscard]] inline Vec3 inv_rotate(const Quat& q, Vec3 v) noexcept {
  return glm::conjugate(q) * v;
}

/// A local point placed in the world by `xf`. (Always inline, as the point helpers below: the
/// 3D contacts call them from large functions, where an out-of-line call passed its Vec3 through
/// the stack: math.hpp.)
[[nodiscard]] COLLIDE_ALWAYS_INLINE Vec3 transform_point(const Transform3& xf, Vec3 local) noexcept {
  return xf.p + xf.q * local;
}
/// A world point expressed in the local frame of `xf`.
[[nodiscard]] COLLIDE_ALWAYS_INLINE Vec3 inv_transform_point(const Transform3& xf, Vec3 world) noexcept {
  return inv_rotate(xf.q, world - xf.p);
}
/// The composition a * b: first b, then a.
[[nodiscard]] inline Transform3 mul(const Transform3& a, const Transform3& b) noexcept {
  return {a.p + a.q * b.p, a.q * b.q};
}
/// a^-1 * b: the frame of b expressed in the frame of a. Queries move shape B into A's local
/// space once, so large world coordinates cancel before any other arithmetic.
[[nodiscard]] inline Transform3 inv_mul(const Transform3& a, const Transform3& b) noexcept {
  const Quat ia = glm::conjugate(a.q);
  return {ia * (b.p - a.p), ia * b.q};
}

/// a^-1 * b * (the translation by `offset`): the frame of points stored relative to `offset` in
/// b's frame (a level's stored frame: TriangleMesh::origin, HeightField::origin) expressed in the
/// frame of a. b's translation and its rotated offset are summed first and a's position taken
/// from that sum, so a level placed at the identity and a body beside its origin, however far
/// both are from the world's, cancel exactly. (Made as b's frame in a's plus the offset rotated
/// into a's, each term rounded at the size of the coordinates: a capsule 7e-15 wide beside a
/// mesh whose origin is 8e-8 from the world's was cast past it, docs/fuzzing.md, finding 26.)
[[nodiscard]] inline Transform3 inv_mul(const Transform3& a, const Transform3& b, Vec3 offset) noexcept {
  const Quat ia = glm::conjugate(a.q);
  return {ia * ((b.p + b.q * offset) - a.p), ia * b.q};
}

/// True when position and rotation are finite and the quaternion is unit length within `tol`
/// (|q|^2 - 1, which is about 2 (|q| - 1)).
[[nodiscard]] inline bool is_valid(const Transform3& xf, float tol = 1e-3f) noexcept {
  const Quat& q = xf.q;
  const float len2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  return is_finite(xf.p) && std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) &&
         std::isfinite(q.z) && std::fabs(len2 - 1.0f) <= tol;
}

/// A rigid transform in matrix form, for inner loops: world = r * local + p.
struct Frame3 {
  Mat3 r{1.0f};              ///< rotation matrix (orthonormal), columns are the local axes
  Vec3 p{0.0f, 0.0f, 0.0f};  ///< translation

  /// The matrix form of `xf`.
  [[nodiscard]] static Frame3 from(const Transform3& xf) noexcept {
    return {glm::mat3_cast(xf.q), xf.p};
  }
};

/// `v` rotated by the frame's rotation.
[[nodiscard]] COLLIDE_ALWAYS_INLINE Vec3 rotate(const Frame3& f, Vec3 v) noexcept { return f.r * v; }
/// `v` rotated by the inverse of the frame's rotation (the transpose).
[[nodiscard]] COLLIDE_ALWAYS_INLINE Vec3 inv_rotate(const Frame3& f, Vec3 v) noexcept {
  return {glm::dot(f.r[0], v), glm::dot(f.r[1], v), glm::dot(f.r[2], v)};
}
/// A local point placed by the frame.
[[nodiscard]] COLLIDE_ALWAYS_INLINE Vec3 transform_point(const Frame3& f, Vec3 local) noexcept {
  return f.r * local + f.p;
}
/// A point expressed in the frame's local space.
[[nodiscard]] COLLIDE_ALWAYS_INLINE Vec3 inv_transform_point(const Frame3& f, Vec3 world) noexcept {
  return inv_rotate(f, world - f.p);
}

/// The rigid transform of D dimensions: `Transform` in 2D, `Transform3` in 3D. For code written
/// once for both (the GJK loop, generic tests).
template <int D>
using TransformN = std::conditional_t<D == 2, Transform, Transform3>;

/// The form of a rigid transform that inner loops use: `Transform` itself in 2D (a rotation is
/// already 4 numbers), the matrix form `Frame3` in 3D.
template <int D>
using FrameN = std::conditional_t<D == 2, Transform, Frame3>;

/// `xf` in the form inner loops use (see FrameN).
[[nodiscard]] inline Transform to_frame(const Transform& xf) noexcept { return xf; }
[[nodiscard]] inline Frame3 to_frame(const Transform3& xf) noexcept { return Frame3::from(xf); }

/// The world box of a local box placed by `xf`: the box around the rotated box, from its centre
/// and |R| times its half extents (Arvo, "Transforming Axis-Aligned Bounding Boxes", Graphics
/// Gems, 1990; Ericson 4.2.6). Tight for rotations by multiples of 90 degrees about the axes.
[[nodiscard]] inline Aabb3 transform_aabb(const Aabb3& local, const Transform3& xf) noexcept {
  const Frame3 f = Frame3::from(xf);
  const Vec3 center = transform_point(f, local.center());
  const Vec3 half = local.extents();
  const Vec3 reach =
      collide::abs(f.r[0]) * half.x + collide::abs(f.r[1]) * half.y + collide::abs(f.r[2]) * half.z;
  return {center - reach, center + reach};
}

}  // namespace collide
