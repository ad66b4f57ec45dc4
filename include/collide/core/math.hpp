#pragma once
/// @file
/// The math layer: glm vectors under short names, plus the few 2D helpers glm does not have
/// (cross products of 2D vectors, perpendiculars). Everything in collide is `float` unless a
/// comment says why not.

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <collide/core/config.hpp>

#include <algorithm>
#include <cmath>

namespace collide {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;

/// z of the 3D cross product of (a, 0) and (b, 0): positive when b is counter-clockwise of a.
[[nodiscard]] constexpr float cross(Vec2 a, Vec2 b) noexcept { return a.x * b.y - a.y * b.x; }
/// Cross of a 2D vector with the scalar z-axis vector s*k: (s*a.y, -s*a.x).
[[nodiscard]] constexpr Vec2 cross(Vec2 a, float s) noexcept { return {s * a.y, -s * a.x}; }
/// Cross of the scalar z-axis vector s*k with a 2D vector: (-s*a.y, s*a.x).
[[nodiscard]] constexpr Vec2 cross(float s, Vec2 a) noexcept { return {-s * a.y, s * a.x}; }
/// `a` rotated 90 degrees counter-clockwise.
[[nodiscard]] constexpr Vec2 left_perp(Vec2 a) noexcept { return {-a.y, a.x}; }
/// `a` rotated 90 degrees clockwise: the outward normal direction of a counter-clockwise edge.
[[nodiscard]] constexpr Vec2 right_perp(Vec2 a) noexcept { return {a.y, -a.x}; }

[[nodiscard]] constexpr float dot(Vec2 a, Vec2 b) noexcept { return a.x * b.x + a.y * b.y; }
[[nodiscard]] constexpr float length_squared(Vec2 a) noexcept { return a.x * a.x + a.y * a.y; }
[[nodiscard]] inline float length(Vec2 a) noexcept { return std::sqrt(length_squared(a)); }
[[nodiscard]] constexpr float distance_squared(Vec2 a, Vec2 b) noexcept {
  return length_squared(b - a);
}
[[nodiscard]] inline float distance(Vec2 a, Vec2 b) noexcept { return length(b - a); }

/// Squared lengths within [kUnitSquaredMin, kUnitSquaredMax] make a unit vector to rounding by
/// one division by their root. Outside it the squares of the components are subnormal or
/// overflow: a closest-point difference about 1e-20 long came out of such a division 0.854 long (the
/// fuzzer's height field contact, finding 28), and a vector longer than about 1e19 came out
/// zero. unit_from and normalize_or_zero scale those by a power of two first.
inline constexpr float kUnitSquaredMin = 0x1p-100f;
inline constexpr float kUnitSquaredMax = 0x1p100f;
/// True when squared length `a2` makes a unit vector to rounding by one division by its root.
[[nodiscard]] constexpr bool unit_squared_in_range(float a2) noexcept {
  return a2 >= kUnitSquaredMin && a2 <= kUnitSquaredMax;
}
/// Vectors with no component longer than this have no direction for normalize_or_zero.
inline constexpr float kNoDirectionLength = 1e-30f;

/// The out-of-line halves of unit_from and normalize_or_zero for squared lengths outside
/// [kUnitSquaredMin, kUnitSquaredMax]: `a` scaled by a power of two (scaled_to_unit_magnitude),
/// then to unit length. unit_of_scaled gives NaN components for a zero or non-finite `a`;
/// normalize_scaled_or_zero gives zero for those and for `a` within kNoDirectionLength.
[[nodiscard]] Vec2 unit_of_scaled(Vec2 a) noexcept;
[[nodiscard]] Vec3 unit_of_scaled(Vec3 a) noexcept;
[[nodiscard]] Vec2 normalize_scaled_or_zero(Vec2 a) noexcept;
[[nodiscard]] Vec3 normalize_scaled_or_zero(Vec3 a) noexcept;

/// `a` (finite, not zero) scaled to unit length, `a2` its squared length as computed
/// (length_squared, or a closest-point routine's distance_squared): unit to rounding at every
/// magnitude, from a subnormal difference to one near float's largest (kUnitSquaredMin).
[[nodiscard]] inline Vec2 unit_from(Vec2 a, float a2) noexcept {
  if (unit_squared_in_range(a2)) [[likely]] return a * (1.0f / std::sqrt(a2));
  return unit_of_scaled(a);
}

/// `a` scaled to unit length (to rounding at every magnitude, kUnitSquaredMin); the zero vector
/// when `a` is too short to have a direction (no component longer than kNoDirectionLength) or
/// not finite.
[[nodiscard]] inline Vec2 normalize_or_zero(Vec2 a) noexcept {
  const float a2 = length_squared(a);
  if (unit_squared_in_range(a2)) [[likely]] return a * (1.0f / std::sqrt(a2));
  return normalize_scaled_or_zero(a);
}

// ---- 3D: the same names for Vec3 (glm's functions, under the names 2D code uses) ----------
// dot and cross always inline: called out of line from a large function (the 3D time of
// impact, 12 calls), their Vec3 arguments go through the stack and come back by loads that
// cannot be forwarded from the stores just made (as triangle_normal's did, stop 85).

/// Dot product a . b (x, y, z in that order: the same rounding everywhere).
[[nodiscard]] COLLIDE_ALWAYS_INLINE constexpr float dot(Vec3 a, Vec3 b) noexcept {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
/// Right-handed cross product a x b.
[[nodiscard]] COLLIDE_ALWAYS_INLINE constexpr Vec3 cross(Vec3 a, Vec3 b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
[[nodiscard]] constexpr float length_squared(Vec3 a) noexcept { return dot(a, a); }
[[nodiscard]] inline float length(Vec3 a) noexcept { return std::sqrt(length_squared(a)); }
[[nodiscard]] constexpr float distance_squared(Vec3 a, Vec3 b) noexcept {
  return length_squared(b - a);
}
[[nodiscard]] inline float distance(Vec3 a, Vec3 b) noexcept { return length(b - a); }
/// The same as the 2D unit_from and normalize_or_zero, for 3D vectors.
[[nodiscard]] inline Vec3 unit_from(Vec3 a, float a2) noexcept {
  if (unit_squared_in_range(a2)) [[likely]] return a * (1.0f / std::sqrt(a2));
  return unit_of_scaled(a);
}
[[nodiscard]] inline Vec3 normalize_or_zero(Vec3 a) noexcept {
  const float a2 = length_squared(a);
  if (unit_squared_in_range(a2)) [[likely]] return a * (1.0f / std::sqrt(a2));
  return normalize_scaled_or_zero(a);
}
/// |a| per component: the sign bits cleared (one and-mask). glm::abs is written as
/// `x >= 0 ? x : -x`, which the compiler must keep as a compare and branch per component (it
/// differs from fabs on -0 and NaN): a misprediction per component on data of random sign.
[[nodiscard]] inline Vec2 abs(Vec2 a) noexcept { return {std::fabs(a.x), std::fabs(a.y)}; }
[[nodiscard]] inline Vec3 abs(Vec3 a) noexcept {
  return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)};
}
/// Largest absolute coordinate: the size that float rounding of `a` is relative to.
[[nodiscard]] inline float max_abs(Vec2 a) noexcept {
  return std::max(std::abs(a.x), std::abs(a.y));
}
[[nodiscard]] inline float max_abs(Vec3 a) noexcept {
  return std::max(std::max(std::abs(a.x), std::abs(a.y)), std::abs(a.z));
}

/// `a` scaled by a power of two (exactly: its direction kept to the bit) to a largest
/// component in [1, 2); NaN components when `a` has no direction (zero, or not finite). For
/// vectors whose squares would leave float's normal range (an edge 1e-19 long, GJK's search
/// direction of a simplex 1e8 across): only their direction is used, and a product of them
/// then neither underflows nor overflows. Out of line: callers take it on rare branches.
[[nodiscard]] Vec2 scaled_to_unit_magnitude(Vec2 a) noexcept;
[[nodiscard]] Vec3 scaled_to_unit_magnitude(Vec3 a) noexcept;
/// The same in double, for a float-cornered triangle's area normal (triangle_area_normal) whose
/// length leaves float's normal range (a needle 1e-22 wide): converted to float after, each
/// component is then float's rounding of the exact one, and a unit normal made from it in float
/// is unit to rounding (from the unscaled normal, whose square was subnormal, it was 1.003 long).
[[nodiscard]] glm::dvec3 scaled_to_unit_magnitude(const glm::dvec3& a) noexcept;

/// Both components finite (not NaN, not infinite).
[[nodiscard]] inline bool is_finite(Vec2 a) noexcept {
  return std::isfinite(a.x) && std::isfinite(a.y);
}
[[nodiscard]] inline bool is_finite(Vec3 a) noexcept {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

}  // namespace collide
