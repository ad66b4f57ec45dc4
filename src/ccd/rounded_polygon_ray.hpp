#pragma once
// Internal to ccd: the ray cast into a polygon rounded by any radius (raycast.cpp), shared by
// `raycast` on rounded polygons and `shape_cast` of a circle or a capsule against a polygon (the
// ray from the circle's centre into the polygon grown by the circle: A - B, literally; for a
// capsule, into the polygon minus its segment, grown by its radius).

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

/// A convex outline: vertices counter-clockwise, edge i from vertex i to vertex i + 1 (mod
/// count) with unit outward normal normals[i]. A polygon's own arrays, or an outline built on
/// the stack (the Minkowski difference of a polygon and a capsule's segment in shape_cast).
struct OutlineView {
  const Vec2* vertices;
  const Vec2* normals;
  int count;
};

/// First entry of p + t d, t in (0, 1], into outline `o` rounded by `radius` (> 0): the
/// method of ray_rounded_polygon. When p starts within the outline of edges pushed out by the
/// radius, `inside` is set and no entry is computed (the caller resolves that start).
[[nodiscard]] LocalHitN<2> ray_rounded_outline(const OutlineView& o, float radius, Vec2 p, Vec2 d,
                                               bool& inside) noexcept;

/// First entry of p + t d, t in (0, 1], into `poly`'s core rounded by `radius` (> 0; the
/// polygon's own radius is ignored), in the polygon's local frame: Cyrus-Beck into the polygon
/// of edges pushed out by the radius, then the corner's disc when the entry lands beyond an
/// edge's end (Ericson, Real-Time Collision Detection, 5.3.8 and 5.3.2). A ray starting in the
/// rounded shape misses.
[[nodiscard]] RoundedPolygonEntry ray_rounded_polygon(const Polygon& poly, float radius, Vec2 p,
                                                      Vec2 d) noexcept;

}  // namespace collide::detail
