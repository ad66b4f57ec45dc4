#pragma once
// Internal: the touching features of two polygons at a contact normal, for the contact point
// of a shape cast (the explicit Minkowski path and the separating-axis path of shape_cast.cpp).

#include <collide/core/aabb.hpp>
#include <collide/shape/polygon.hpp>

#include <algorithm>
#include <cmath>

namespace collide::detail {

/// Fraction of the shapes' size within which two vertices count as equally far along the
/// normal: they then form the touching edge rather than a touching vertex.
inline constexpr float kFeatureTieTolerance = 1e-4f;

/// Where along the tangent `u` and the normal `n` the touching features of A and B lie: the
/// core vertices farthest along n on A and against n on B, each set's extent along u.
struct TouchingFeature {
  float height = 0.0f;  ///< along n: the core's extreme
  float lo = 0.0f;      ///< along u: the feature's extent
  float hi = 0.0f;
};

/// The points `point(0..count-1)` (a core's vertices, placed) extreme along `sign * n`, within
/// `tie`; u = left_perp(n).
template <class Point>
inline TouchingFeature touching_feature(int count, Point&& point, Vec2 n, float sign,
                                        float tie) noexcept {
  float best = -INFINITY;
  for (int i = 0; i < count; ++i) best = std::max(best, sign * dot(point(i), n));
  const Vec2 u = left_perp(n);
  TouchingFeature f{sign * best, INFINITY, -INFINITY};
  for (int i = 0; i < count; ++i) {
    const Vec2 p = point(i);
    if (sign * dot(p, n) >= best - tie) {
      f.lo = std::min(f.lo, dot(p, u));
      f.hi = std::max(f.hi, dot(p, u));
    }
  }
  return f;
}

/// The contact point of two touching features, in their frame: the middle of their overlap
/// along the tangent (vertex against edge: the vertex; edge against edge: the middle of the
/// shared part), and along n midway between the surfaces (cores' extremes pushed out by the
/// radii).
inline Vec2 touching_point(const TouchingFeature& fa, float radius_a, const TouchingFeature& fb,
                           float radius_b, Vec2 n) noexcept {
  const float lo = std::max(fa.lo, fb.lo);
  const float hi = std::min(fa.hi, fb.hi);
  const float along = 0.5f * (lo + hi);
  const float across = 0.5f * ((fa.height + radius_a) + (fb.height - radius_b));
  return along * left_perp(n) + across * n;
}

}  // namespace collide::detail
