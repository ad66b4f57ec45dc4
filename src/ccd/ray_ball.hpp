#pragma once
/// @file
/// The ray-ball entry shared by the 2D and 3D ray casts (a circle, a sphere, the end caps of
/// capsules, the corners of rounded polygons and boxes). Internal to ccd.

#include <collide/core/aabb.hpp>

#include <cmath>

namespace collide::detail {

/// A hit in a shape's local frame: fraction along the ray and unit outward normal (local).
template <int D>
struct LocalHitN {
  bool hit = false;
  float fraction = 0.0f;
  VecN<D> normal{0.0f};
};

/// First entry of the ray m + t d, t in [0, 1], into the ball of `radius` about the origin
/// (m is the ray's origin relative to the ball's centre), in D dimensions. Ericson, Real-Time
/// Collision Detection, 5.3.2, with the discriminant computed from the ray's closest approach to
/// the centre (r^2 - |m_perp|^2) instead of b^2 - c, which cancels badly for rays that pass far
/// away (Haines et al., "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems
/// 7). One division; the normal is the hit point over the radius, which is unit by
/// construction. An origin in the closed ball, a zero-length ray and NaN all miss.
template <int D>
[[nodiscard]] inline LocalHitN<D> ray_ball(VecN<D> m, VecN<D> d, float radius) noexcept {
  const float c = length_squared(m) - radius * radius;
  const float b = dot(m, d);
  // Origin in the closed ball (no entry), or outside and not heading towards the centre.
  if (!(c > 0.0f) || b >= 0.0f) return {};
  const float inv_dd = 1.0f / length_squared(d);
  const float tc = -b * inv_dd;        // parameter of the closest approach
  const VecN<D> closest = m + tc * d;  // centre to closest approach
  const float disc = radius * radius - length_squared(closest);
  if (disc < 0.0f) return {};
  const float t = tc - std::sqrt(disc * inv_dd);
  if (!(t <= 1.0f)) return {};
  // A zero-radius ball hit dead on has no surface direction: face the ray.
  const VecN<D> n = radius > 0.0f ? (m + t * d) * (1.0f / radius) : -d * std::sqrt(inv_dd);
  return {true, t > 0.0f ? t : 0.0f, n};
}

}  // namespace collide::detail
