#pragma once
// Internal: the contact routines behind the dispatch table in contact.cpp. Each is written for
// one order of its pair; the table serves the other order through `reversed`. Capsules and
// segments reach `contact_polygons` and `contact_polygon_circle` as 2-vertex polygons, and
// `contact_polygon_segment` (as B) as their core.

#include <collide/core/math.hpp>
#include <collide/core/transform.hpp>
#include <collide/narrow/manifold.hpp>
#include <collide/shape/circle.hpp>
#include <collide/shape/polygon.hpp>

namespace collide::detail {

/// A capsule's or segment's core as `contact_polygon_segment` takes it: the points b0 -> b1, the
/// unit normal of edge 0 (right of b0 -> b1, two_vertex_polygon's; zero when the points
/// coincide; edge 1's is its negative) and the rounding radius.
struct SegmentCore {
  Vec2 b0{0.0f, 0.0f};
  Vec2 b1{0.0f, 0.0f};
  Vec2 normal{0.0f, 0.0f};
  float radius = 0.0f;
};

/// The core of a capsule or segment from b0 to b1.
inline SegmentCore segment_core(Vec2 b0, Vec2 b1, float radius) noexcept {
  return {b0, b1, normalize_or_zero(right_perp(b1 - b0)), radius};
}

/// The 2-vertex polygon of a capsule or segment: edge 0 runs a -> b with its normal to the
/// right, edge 1 runs b -> a. Only the first two slots are written (inline storage, no fill).
inline Polygon two_vertex_polygon(Vec2 a, Vec2 b, float radius) noexcept {
  Polygon p;  // NOLINT: arrays deliberately left unset beyond count
  p.count = 2;
  p.vertices[0] = a;
  p.vertices[1] = b;
  const Vec2 n = segment_core(a, b, radius).normal;
  p.normals[0] = n;
  p.normals[1] = -n;
  p.centroid = 0.5f * (a + b);
  p.radius = radius;
  return p;
}

/// Two circles: analytic (circle_contact.cpp).
[[nodiscard]] Manifold contact_circles(const Circle& a, const Transform& xa, const Circle& b,
                                       const Transform& xb) noexcept;

/// A polygon (or 2-vertex polygon) and a circle: Voronoi region of the circle's centre
/// (Ericson 5.2.7; circle_contact.cpp).
[[nodiscard]] Manifold contact_polygon_circle(const Polygon& a, const Transform& xa,
                                              const Circle& b, const Transform& xb) noexcept;

/// Two polygons (or 2-vertex polygons): separating axis test, then reference face and incident
/// edge clipping, or closest core features for rounded shapes whose cores are apart
/// (polygon_contact.cpp).
[[nodiscard]] Manifold contact_polygons(const Polygon& a, const Transform& xa, const Polygon& b,
                                        const Transform& xb) noexcept;

/// `contact_polygons(a, xa, two_vertex_polygon(b...), xb)`, bit for bit, without building B's
/// polygon: B's separating axis pass is one row of dot products (polygon_contact.cpp).
[[nodiscard]] Manifold contact_polygon_segment(const Polygon& a, const Transform& xa,
                                               const SegmentCore& b,
                                               const Transform& xb) noexcept;

/// `contact_polygons` with every pair on the general front end (polygons copied into 4-wide
/// arrays), never the small-polygon one: the reference that tests/narrow hold the small-polygon
/// path to, bit for bit.
[[nodiscard]] Manifold contact_polygons_general_path(const Polygon& a, const Transform& xa,
                                                     const Polygon& b,
                                                     const Transform& xb) noexcept;

}  // namespace collide::detail
