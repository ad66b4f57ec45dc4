#pragma once
// Private to src/decompose: the one corner test every decomposition step shares, written exactly
// as make_convex_polygon writes it, so a piece accepted here is accepted there.

#include <collide/core/math.hpp>
#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <span>

namespace collide::detail {

/// Twice the signed area of the corner prev -> cur -> next: > 0 turns left (convex in a
/// counter-clockwise outline), < 0 turns right (reflex), 0 straight.
[[nodiscard]] inline float corner_turn(Vec2 prev, Vec2 cur, Vec2 next) noexcept {
  return cross(cur - prev, next - cur);
}

/// Size of a point set (largest side of its bounding box): the scale tolerances follow.
[[nodiscard]] inline float outline_size(std::span<const Vec2> points) noexcept {
  Vec2 lo = points[0];
  Vec2 hi = points[0];
  for (Vec2 p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return std::max(hi.x - lo.x, hi.y - lo.y);
}

/// A turn at most this large in magnitude is straight: kDegenerateAreaTolerance of the squared
/// size, the same rule make_polygon and make_convex_polygon apply. Pieces are never larger than
/// their outline, so a corner that passes here passes their test too.
[[nodiscard]] inline float straight_turn_tolerance(float size) noexcept {
  return kDegenerateAreaTolerance * size * size;
}

}  // namespace collide::detail
