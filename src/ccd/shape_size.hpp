#pragma once
/// @file
/// The size of a shape that the continuous collision tolerances scale with. Internal.

#include <collide/narrow/support.hpp>

#include <algorithm>

namespace collide::detail {

/// The shape's size, estimated in O(1): the distance between two core points half-way
/// around the core from each other (a polygon's vertex 0 and vertex count/2, a capsule's two
/// ends), plus the radius. For convex polygons, about the diameter (at least half of it for
/// any reasonable vertex spacing); exact for circles, capsules and segments. A full pass over
/// the vertices cost 8% of a shape cast and bought nothing a tolerance needs.
/// In 3D the pair is point 0 and the last point (a box's opposite corners).
[[nodiscard]] inline float proxy_size(const ConvexProxy& p) noexcept {
  return distance(p.point(0), p.point(p.count() / 2)) + p.radius();
}
[[nodiscard]] inline float proxy_size(const ConvexProxy3& p) noexcept {
  return distance(p.point(0), p.point(p.count() - 1)) + p.radius();
}

/// The smaller of two sizes, unless it is zero (a point), then the larger.
[[nodiscard]] inline float smaller_size(float size_a, float size_b) noexcept {
  const float smaller = std::min(size_a, size_b);
  return smaller > 0.0f ? smaller : std::max(size_a, size_b);
}

}  // namespace collide::detail
