#pragma once
/// @file
/// The ray-ball entry shared by the 2D and 3D ray casts (a circle, a sphere, the end caps of
/// capsules, the corners of rounded polygons and boxes). Internal to ccd.

#include <collide/core/aabb.hpp>
#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace collide::detail {

/// A hit in a shape's local frame: fraction along the ray and unit outward normal (local).
template <int D>
struct LocalHitN {
  bool hit = false;
  float fraction = 0.0f;
  VecN<D> normal{0.0f};
};

/// `x` where `keep` is all ones, +0 where it is zero: a select without a branch (a ternary on
/// floats often compiles to one, and random rays mispredict it).
[[nodiscard]] inline float keep_if(float x, std::uint32_t keep) noexcept {
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(x) & keep);
}

/// All ones if `b`, else zero: the mask of keep_if.
[[nodiscard]] inline std::uint32_t mask_of(bool b) noexcept {
  return 0u - static_cast<std::uint32_t>(b);
}

/// The capsule casts' early out (2D and 3D) takes a ray for a miss only when it stays farther
/// than (1 + this) r from the capsule's core line (3D: its line passes farther than
/// sqrt(1 + this) r; squared distances are compared there): a grazing ray goes on to the full
/// cast, whose own rounding decides as it did without the early out.
inline constexpr float kCapsuleMissSlack = 0.01f;

/// True when a ball (or a capsule's ends) of this radius has directions to give: r^2 at least
/// kMinDirectionLengthSquared (r above about 1e-19). Below it r^2 is denormal or zero, the hit
/// offset too small to normalise, and the piece is cast as a point (or segment), facing the ray.
[[nodiscard]] inline bool is_round(float radius) noexcept {
  return radius * radius >= kMinDirectionLengthSquared;
}

/// First entry of the ray m + t d, t in [0, 1], into the ball of `radius` about the origin
/// (m is the ray's origin relative to the ball's centre), in D dimensions. Ericson, Real-Time
/// Collision Detection, 5.3.2, with the discriminant computed from the ray's closest approach to
/// the centre (r^2 - |m_perp|^2) instead of b^2 - c, which cancels badly for rays that pass far
/// away (Haines et al., "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems
/// 7). The normal is the hit point's offset from the centre made unit: not divided by the
/// radius, since a ray from far away (relative to the radius) rounds that offset by eps times
/// the distance, and the quotient was off unit length by as much relative to r (0.9995 long for
/// a ray from 1e5 radii away). Where the offset has no direction (its squared length below
/// kMinDirectionLengthSquared: the ray hits dead on within rounding, as fuzz_shapes found with
/// a radius of 1e-20, then NaN or zero) or the ball is a point (r^2 below it, r under about
/// 1e-19), the normal faces the ray. An origin in the closed ball, a zero-length ray and NaN
/// all miss (every field zero). Without branches on the data but that rare one: the conditions
/// are gathered into a mask that zeroes a miss's fields (random rays hit or miss at random;
/// bench_ray_cast, circles visited in an order the branch predictor cannot learn: 14 -> 11 ns
/// on the AMD EPYC host of stop 49). The normalisation cost 2 ns a circle cast (stop 59,
/// bench_ray_cast alternating: 15.0-16.4 -> 17.4-18.6 ns), won back and more by masking the
/// fraction before its clamp, a branch on misses before (15.0-15.8 ns); neither a Newton step
/// for 1 / sqrt nor an offset whose length is r to second order (closest approach made
/// perpendicular to d again, then over r) measured faster.
template <int D>
[[nodiscard]] inline LocalHitN<D> ray_ball(VecN<D> m, VecN<D> d, float radius) noexcept {
  const float rr = radius * radius;
  const float c = length_squared(m) - rr;
  const float b = dot(m, d);
  const float inv_dd = 1.0f / length_squared(d);
  const float tc = -b * inv_dd;        // parameter of the closest approach
  const VecN<D> closest = m + tc * d;  // centre to closest approach
  const float disc = rr - length_squared(closest);
  const float t = tc - std::sqrt(std::max(disc, 0.0f) * inv_dd);
  // Origin outside the closed ball and heading towards the centre, a line that reaches the
  // ball, and an entry within the ray's length.
  const bool hit = (c > 0.0f) & (b < 0.0f) & (disc >= 0.0f) & (t <= 1.0f);
  // The offset made unit; where it has no direction (or the ball is a point), face the ray.
  const VecN<D> offset = m + t * d;
  const float ll = length_squared(offset);
  VecN<D> n = offset * (1.0f / std::sqrt(ll));
  const std::uint32_t keep = mask_of(hit);
  // One integer test, so that the compiler cannot branch on a miss's (random) length first.
  const std::uint32_t no_direction = keep & (mask_of(!is_round(radius)) |
                                             mask_of(!(ll >= kMinDirectionLengthSquared)));
  if (no_direction != 0u) [[unlikely]] n = -d * std::sqrt(inv_dd);
  LocalHitN<D> h;
  h.hit = hit;
  // Masked before the clamp: GCC compiles this max as a branch, which a miss's random t
  // mispredicted (t < 0 only by rounding on a hit; a miss's masked t is +0).
  h.fraction = std::max(keep_if(t, keep), 0.0f);
  for (int k = 0; k < D; ++k) h.normal[k] = keep_if(n[k], keep);
  return h;
}

}  // namespace collide::detail
