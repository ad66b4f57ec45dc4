#pragma once
/// @file
/// The size of a shape that the continuous collision tolerances scale with. Internal.

#include <collide/narrow/support.hpp>

#include <algorithm>
#include <cmath>

namespace collide::detail {

/// Reach of the proxy's core from its first point, plus its radius: a size within a factor 2
/// of the shape's diameter, in one pass with no square root per point.
[[nodiscard]] inline float proxy_size(const ConvexProxy& p) noexcept {
  const Vec2 p0 = p.point(0);
  float r2 = 0.0f;
  for (int i = 1; i < p.count(); ++i) r2 = std::max(r2, distance_squared(p0, p.point(i)));
  return std::sqrt(r2) + p.radius();
}

/// The smaller of two sizes, unless it is zero (a point), then the larger.
[[nodiscard]] inline float smaller_size(float size_a, float size_b) noexcept {
  const float smaller = std::min(size_a, size_b);
  return smaller > 0.0f ? smaller : std::max(size_a, size_b);
}

}  // namespace collide::detail
