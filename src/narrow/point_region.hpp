#pragma once
// Internal: which part of a polygon's outline is closest to a point beyond one of its edges,
// shared by the polygon-circle contact (circle_contact.cpp) and distance (distance.cpp).

#include <collide/core/math.hpp>
#include <collide/shape/polygon.hpp>

namespace collide::detail {

/// For a point `c` (the polygon's frame) beyond edge `edge` of `p` (from vertex `edge` to
/// vertex `next`), the end of the edge whose Voronoi region holds c when c's foot on the edge's
/// line falls before the first end (returns `edge`) or after the second (returns `next`);
/// -1 when the foot lies on the edge (the edge's region). When `edge` is the edge of greatest
/// separation of c, this region is the closest feature of the whole polygon (Ericson,
/// Real-Time Collision Detection, 5.2.7).
[[nodiscard]] inline int edge_end_region(const Polygon& p, int edge, int next, Vec2 c) noexcept {
  const Vec2 v1 = p.vertices[edge];
  const Vec2 v2 = p.vertices[next];
  if (dot(c - v1, v2 - v1) < 0.0f) return edge;
  if (dot(c - v2, v1 - v2) < 0.0f) return next;
  return -1;
}

}  // namespace collide::detail
