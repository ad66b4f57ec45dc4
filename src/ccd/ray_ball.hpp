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

/// `a` if `c`, else `b`, by masks: no branch.
[[nodiscard]] inline float pick(bool c, float a, float b) noexcept {
  const std::uint32_t m = mask_of(c);
  return std::bit_cast<float>((std::bit_cast<std::uint32_t>(a) & m) |
                              (std::bit_cast<std::uint32_t>(b) & ~m));
}

/// First entry of the ray m + t d, t in [0, 1], into the ball of `radius` about the origin
/// (m is the ray's origin relative to the ball's centre), in D dimensions. Ericson, Real-Time
/// Collision Detection, 5.3.2, with the discriminant computed from the ray's closest approach to
/// the centre (r^2 - |m_perp|^2) instead of b^2 - c, which cancels badly for rays that pass far
/// away (Haines et al., "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems
/// 7). The normal is the hit point's offset from the centre made unit (not divided by the
/// radius: a ray from far away, relative to the radius, rounds that offset by more than the
/// radius' float precision, so the quotient can be off unit length by eps * distance / radius);
/// where the offset has no direction (a zero radius, or an offset below
/// kMinDirectionLengthSquared: the ray hits dead on within rounding) it faces the ray. An origin
/// in the closed ball, a zero-length ray and NaN all miss (every field zero). Without branches: the conditions are gathered into a mask that zeroes a miss's fields
/// (random rays hit or miss at random; bench_ray_cast, circles visited in an order the branch
/// predictor cannot learn: 14 -> 11 ns on the AMD EPYC host of stop 49).
template <int D>
[[nodiscard]] inline LocalHitN<D> ray_ball(VecN<D> m, VecN<D> d, float radius) noexcept {
  const float c = length_squared(m) - radius * radius;
  const float b = dot(m, d);
  const float inv_dd = 1.0f / length_squared(d);
  const float tc = -b * inv_dd;        // parameter of the closest approach
  const VecN<D> closest = m + tc * d;  // centre to closest approach
  const float disc = radius * radius - length_squared(closest);
  const float t = tc - std::sqrt(std::max(disc, 0.0f) * inv_dd);
  // Origin outside the closed ball and heading towards the centre, a line that reaches the
  // ball, and an entry within the ray's length.
  const bool hit = (c > 0.0f) & (b < 0.0f) & (disc >= 0.0f) & (t <= 1.0f);
  const VecN<D> offset = m + t * d;
  const float offset_ll = length_squared(offset);
  const bool towards_centre = (radius > 0.0f) & (offset_ll >= kMinDirectionLengthSquared);
  const float scale = 1.0f / std::sqrt(offset_ll);
  const float face = -std::sqrt(inv_dd);
  const std::uint32_t keep = mask_of(hit);
  LocalHitN<D> h;
  h.hit = hit;
  h.fraction = keep_if(std::max(t, 0.0f), keep);
  for (int k = 0; k < D; ++k) h.normal[k] = keep_if(pick(towards_centre, offset[k] * scale, d[k] * face), keep);
  return h;
}

}  // namespace collide::detail
