#pragma once
// Internal to ccd: the ray cast into a polygon rounded by any radius (raycast.cpp), shared by
// `raycast` on rounded polygons and `shape_cast` of a circle against a polygon (the ray from
// the circle's centre into the polygon grown by the circle: A - B, literally).

#include <collide/shape/polygon.hpp>

#include "ray_ball.hpp"

#include <cmath>

namespace collide::detail {

/// The answer of ray_rounded_polygon.
struct RoundedPolygonEntry {
  LocalHitN<2> hit;  ///< first entry, fraction in (0, 1], outward unit normal (local frame)
  /// The origin's distance to the rounded shape when it starts within the polygon of edges
  /// pushed out by the radius (<= 0: in the shape; > 0: in a corner's kite, outside it);
  /// infinity when it starts outside that polygon (then it is at least as far as the closest
  /// pushed-out edge's line).
  float start_gap = INFINITY;
};

/// First entry of p + t d, t in (0, 1], into `poly`'s core rounded by `radius` (> 0; the
/// polygon's own radius is ignored), in the polygon's local frame: Cyrus-Beck into the polygon
/// of edges pushed out by the radius, then the corner's disc when the entry lands beyond an
/// edge's end (Ericson, Real-Time Collision Detection, 5.3.8 and 5.3.2). A ray starting in the
/// rounded shape misses.
[[nodiscard]] RoundedPolygonEntry ray_rounded_polygon(const Polygon& poly, float radius, Vec2 p,
                                                      Vec2 d) noexcept;

}  // namespace collide::detail
