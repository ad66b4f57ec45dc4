// Point queries by Voronoi regions (Ericson, Real-Time Collision Detection, 5.1): find the
// feature of the shape's core whose region holds the point, take the closest point on that
// feature, then apply the radius along the direction from the core to the point.
//
// The point is moved into the shape's local frame first (large coordinates cancel before any
// other arithmetic); the answer is moved back once.

#include <collide/narrow/closest_point.hpp>

#include <cmath>

namespace collide {
namespace {

/// A point query on the core in local space, before the radius is applied.
struct CoreQuery {
  float distance = 0.0f;  ///< signed distance to the core: negative inside a polygon core
  Vec2 closest{0.0f, 0.0f};
  /// Unit direction from the core's closest point towards the outside of the surface.
  Vec2 outward{0.0f, 0.0f};
  Feature feature{};
};

/// Grow the core answer by `radius` and place it in the world.
PointQuery finish(const CoreQuery& q, float radius, const Transform& xf) noexcept {
  PointQuery out;
  out.distance = q.distance - radius;
  out.inside = out.distance < 0.0f;
  out.closest = transform_point(xf, q.closest + radius * q.outward);
  out.feature = q.feature;
  return out;
}

/// The closest point on segment a-b to p, as a capsule/segment core: vertex 0 or 1 in the end
/// regions, otherwise edge 0 (right of a -> b, including the segment itself) or edge 1.
/// Ericson 5.1.2.
CoreQuery segment_core(Vec2 a, Vec2 b, Vec2 p) noexcept {
  const Vec2 e = b - a;
  const Vec2 rel = p - a;
  const float s = dot(rel, e);
  const float ee = length_squared(e);
  const Vec2 right = right_perp(e) * (1.0f / std::sqrt(ee));
  CoreQuery q;
  if (s <= 0.0f || s >= ee) {
    const bool at_a = s <= 0.0f;
    q.closest = at_a ? a : b;
    q.feature = {FeatureType::vertex, at_a ? 0u : 1u};
    const Vec2 away = p - q.closest;
    q.distance = length(away);
    // On the vertex itself: point out along the axis, away from the other end.
    const Vec2 axis = e * (1.0f / std::sqrt(ee));
    q.outward = q.distance > 0.0f ? away * (1.0f / q.distance) : (at_a ? -axis : axis);
    return q;
  }
  const float side = dot(rel, right);  // > 0: right of a -> b
  q.closest = a + (s / ee) * e;
  q.distance = std::fabs(side);
  const bool on_right = side >= 0.0f;
  q.feature = {FeatureType::edge, on_right ? 0u : 1u};
  q.outward = on_right ? right : -right;
  return q;
}

/// Convex polygon core. The edge of greatest separation n_i . (p - v_i) decides:
/// - inside (every separation <= 0): the nearest edge line is the edge of least penetration and
///   the projection onto it lies on the edge (a nearer boundary point would be on a nearer line).
/// - outside: the exterior is partitioned into Voronoi regions, in counter-clockwise order
///   V0, E0, V1, E1, ...: vertex i's region is the wedge between the normals of edges i - 1 and
///   i (the normal cone), edge i's region the slab over edge i outside its line. Walk through
///   them from the most separating edge, backwards if p projects before its start, forwards
///   otherwise; the walk usually ends at the first or second region and never exceeds a lap.
///   Ericson 5.1.
CoreQuery polygon_core(const Polygon& poly, Vec2 p) noexcept {
  const int n = poly.count;
  int best = 0;
  float best_sep = dot(poly.normals[0], p - poly.vertices[0]);
  for (int i = 1; i < n; ++i) {
    const float sep = dot(poly.normals[i], p - poly.vertices[i]);
    if (sep > best_sep) {
      best_sep = sep;
      best = i;
    }
  }
  CoreQuery q;
  auto edge_answer = [&](int i, float sep) {
    q.distance = sep;
    q.closest = p - sep * poly.normals[i];
    q.outward = poly.normals[i];
    q.feature = {FeatureType::edge, static_cast<std::uint32_t>(i)};
    return q;
  };
  if (best_sep <= 0.0f) return edge_answer(best, best_sep);

  auto next = [n](int i) { return i + 1 < n ? i + 1 : 0; };
  auto prev = [n](int i) { return i > 0 ? i - 1 : n - 1; };
  auto in_vertex_region = [&](int i) {
    const Vec2 v = poly.vertices[i];
    return dot(p - v, v - poly.vertices[prev(i)]) >= 0.0f &&
           dot(p - v, poly.vertices[next(i)] - v) <= 0.0f;
  };
  auto in_edge_region = [&](int i) {
    const Vec2 v = poly.vertices[i];
    const Vec2 w = poly.vertices[next(i)];
    return dot(p - v, w - v) >= 0.0f && dot(p - w, w - v) <= 0.0f &&
           dot(poly.normals[i], p - v) >= 0.0f;
  };
  auto vertex_answer = [&](int i) {
    q.closest = poly.vertices[i];
    const Vec2 away = p - q.closest;
    q.distance = length(away);
    q.outward = q.distance > 0.0f ? away * (1.0f / q.distance) : poly.normals[i];
    q.feature = {FeatureType::vertex, static_cast<std::uint32_t>(i)};
    return q;
  };
  const Vec2 v0 = poly.vertices[best];
  if (dot(p - v0, poly.vertices[next(best)] - v0) < 0.0f) {
    for (int i = best, step = 0; step < n; ++step, i = prev(i)) {  // V_i, E_{i-1}, V_{i-1}...
      if (in_vertex_region(i)) return vertex_answer(i);
      if (in_edge_region(prev(i))) {
        return edge_answer(prev(i), dot(poly.normals[prev(i)], p - poly.vertices[prev(i)]));
      }
    }
  } else {
    for (int i = best, step = 0; step < n; ++step, i = next(i)) {  // E_i, V_{i+1}, E_{i+1}...
      if (in_edge_region(i)) return edge_answer(i, dot(poly.normals[i], p - poly.vertices[i]));
      if (in_vertex_region(next(i))) return vertex_answer(next(i));
    }
  }
  // Only reachable when rounding puts p on no side of a region boundary: the best edge's
  // projection is then within rounding of the answer.
  return edge_answer(best, best_sep);
}

CoreQuery core_query(const Circle& circle, Vec2 p) noexcept {
  const Vec2 away = p - circle.center;
  CoreQuery q;
  q.distance = length(away);
  q.closest = circle.center;
  // At the centre every direction is closest: report +x.
  q.outward = q.distance > 0.0f ? away * (1.0f / q.distance) : Vec2{1.0f, 0.0f};
  q.feature = {FeatureType::face, 0};
  return q;
}

CoreQuery core_query(const Capsule& capsule, Vec2 p) noexcept {
  return segment_core(capsule.a, capsule.b, p);
}

CoreQuery core_query(const Segment& segment, Vec2 p) noexcept {
  return segment_core(segment.a, segment.b, p);
}

CoreQuery core_query(const Polygon& polygon, Vec2 p) noexcept { return polygon_core(polygon, p); }

float radius_of(const Circle& s) noexcept { return s.radius; }
float radius_of(const Capsule& s) noexcept { return s.radius; }
float radius_of(const Polygon& s) noexcept { return s.radius; }
float radius_of(const Segment&) noexcept { return 0.0f; }

}  // namespace

template <Shape2DType S>
PointQuery closest_point(const S& shape, const Transform& xf, Vec2 point) noexcept {
  const Vec2 local = inv_transform_point(xf, point);
  return finish(core_query(shape, local), radius_of(shape), xf);
}

template PointQuery closest_point(const Circle&, const Transform&, Vec2) noexcept;
template PointQuery closest_point(const Capsule&, const Transform&, Vec2) noexcept;
template PointQuery closest_point(const Polygon&, const Transform&, Vec2) noexcept;
template PointQuery closest_point(const Segment&, const Transform&, Vec2) noexcept;

PointQuery closest_point(const Shape2D& shape, const Transform& xf, Vec2 point) noexcept {
  return std::visit([&](const auto& s) { return closest_point(s, xf, point); }, shape);
}

}  // namespace collide
