#pragma once
/// @file
/// 2D rotations and rigid transforms. A shape is stored in local space; a `Transform` places it
/// in the world: world = p + R * local.

#include <collide/core/math.hpp>

#include <cmath>

namespace collide {

/// A 2D rotation stored as cosine and sine of the angle (counter-clockwise, radians), as Box2D's
/// b2Rot: rotating a vector costs 4 multiplies and no trigonometry.
struct Rot2 {
  float c = 1.0f;  ///< cos(angle)
  float s = 0.0f;  ///< sin(angle)

  /// The rotation by `radians`, counter-clockwise.
  [[nodiscard]] static Rot2 from_angle(float radians) noexcept {
    return {std::cos(radians), std::sin(radians)};
  }
  /// The angle in radians, in [-pi, pi].
  [[nodiscard]] float angle() const noexcept { return std::atan2(s, c); }
};

/// `v` rotated by `q`.
[[nodiscard]] constexpr Vec2 rotate(Rot2 q, Vec2 v) noexcept {
  return {q.c * v.x - q.s * v.y, q.s * v.x + q.c * v.y};
}
/// `v` rotated by the inverse of `q`.
[[nodiscard]] constexpr Vec2 inv_rotate(Rot2 q, Vec2 v) noexcept {
  return {q.c * v.x + q.s * v.y, -q.s * v.x + q.c * v.y};
}
/// The rotation q * r (r first, then q).
[[nodiscard]] constexpr Rot2 mul(Rot2 q, Rot2 r) noexcept {
  return {q.c * r.c - q.s * r.s, q.s * r.c + q.c * r.s};
}
/// The rotation q^-1 * r.
[[nodiscard]] constexpr Rot2 inv_mul(Rot2 q, Rot2 r) noexcept {
  return {q.c * r.c + q.s * r.s, q.c * r.s - q.s * r.c};
}

/// A 2D rigid transform: world = p + q * local. Default is the identity.
struct Transform {
  Vec2 p{0.0f, 0.0f};  ///< translation, world units
  Rot2 q{};            ///< rotation

  /// The transform that rotates by `radians` (counter-clockwise) and then moves to `position`.
  [[nodiscard]] static Transform from(Vec2 position, float radians) noexcept {
    return {position, Rot2::from_angle(radians)};
  }
};

/// `v` rotated by the transform's rotation (no translation).
[[nodiscard]] constexpr Vec2 rotate(const Transform& xf, Vec2 v) noexcept {
  return rotate(xf.q, v);
}
/// `v` rotated by the inverse of the transform's rotation (no translation).
[[nodiscard]] constexpr Vec2 inv_rotate(const Transform& xf, Vec2 v) noexcept {
  return inv_rotate(xf.q, v);
}

/// A local point placed in the world by `xf`.
[[nodiscard]] constexpr Vec2 transform_point(const Transform& xf, Vec2 local) noexcept {
  return xf.p + rotate(xf.q, local);
}
/// A world point expressed in the local frame of `xf`.
[[nodiscard]] constexpr Vec2 inv_transform_point(const Transform& xf, Vec2 world) noexcept {
  return inv_rotate(xf.q, world - xf.p);
}
/// The composition a * b: first b, then a.
[[nodiscard]] constexpr Transform mul(const Transform& a, const Transform& b) noexcept {
  return {rotate(a.q, b.p) + a.p, mul(a.q, b.q)};
}
/// a^-1 * b: the frame of b expressed in the frame of a. Used to move shape B into A's local
/// space once before a loop, so large world coordinates cancel before any other arithmetic.
[[nodiscard]] constexpr Transform inv_mul(const Transform& a, const Transform& b) noexcept {
  return {inv_rotate(a.q, b.p - a.p), inv_mul(a.q, b.q)};
}

/// True when position and rotation are finite and the rotation is unit length within `tol`.
[[nodiscard]] inline bool is_valid(const Transform& xf, float tol = 1e-3f) noexcept {
  const float len2 = xf.q.c * xf.q.c + xf.q.s * xf.q.s;
  return is_finite(xf.p) && std::isfinite(xf.q.c) && std::isfinite(xf.q.s) &&
         std::fabs(len2 - 1.0f) <= tol;
}

}  // namespace collide
