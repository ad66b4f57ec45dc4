#pragma once
/// @file
/// Convex polygons with an optional rounding radius, stored inline (no heap) so queries on them
/// never allocate.

#include <collide/core/aabb.hpp>
#include <collide/core/transform.hpp>

#include <array>
#include <span>

namespace collide {

/// Most vertices a Polygon holds. Queries keep every temporary on the stack at this size.
inline constexpr int kMaxPolygonVertices = 64;

/// A convex polygon, counter-clockwise, in local space, optionally rounded: the solid set of
/// points within `radius` of the convex hull of `vertices`. Edge i runs from vertex i to vertex
/// i + 1 (mod count) and `normals[i]` is its unit outward normal.
///
/// Build polygons with `make_polygon`, `make_convex_polygon` or `make_box`, which establish the
/// invariants (3..kMaxPolygonVertices distinct vertices, strictly convex, counter-clockwise,
/// finite); treat the fields as read-only afterwards. Inside collide, capsules and segments are
/// also seen as 2-vertex polygons (count 2), which public constructors never produce.
///
/// Size: about 1 KiB (vertex and normal arrays are inline). Aligned to a cache line so that a
/// small polygon touches two lines in a query (the header with its first vertices, and its
/// first normals) wherever it sits in an array (unaligned, one in four straddled four lines;
/// circle-polygon contact over 1024 polygons in an array was 6% slower, bench_narrow_contact).
struct alignas(64) Polygon {
  // Small fields first: a query on a small polygon then touches the count, the radius and the
  // first vertices in neighbouring cache lines rather than lines 1 KiB apart.
  int count = 0;                                   ///< number of vertices
  float radius = 0.0f;                             ///< rounding radius, >= 0
  Vec2 centroid{0.0f, 0.0f};                       ///< area centroid of the core, local space
  std::array<Vec2, kMaxPolygonVertices> vertices;  ///< local space, counter-clockwise
  std::array<Vec2, kMaxPolygonVertices> normals;   ///< unit outward normal of edge i

  /// Vertex i wrapped modulo count.
  [[nodiscard]] Vec2 vertex(int i) const noexcept { return vertices[static_cast<size_t>(i % count)]; }
};

/// The convex hull of `points` as a polygon, with rounding `radius`. Points may come in any
/// order; duplicates (within kWeldTolerance of the point set's size) and collinear points are
/// dropped. Throws InvalidInput naming the problem if: a coordinate is not finite; the radius
/// is negative or not finite; fewer than 3 distinct points remain or they are all collinear
/// (zero area); the hull has more than kMaxPolygonVertices vertices.
/// Algorithm: Andrew's monotone chain (Andrew 1979; de Berg et al. 1.1), O(n log n).
[[nodiscard]] Polygon make_polygon(std::span<const Vec2> points, float radius = 0.0f);

/// A polygon from vertices the caller promises are convex and counter-clockwise, kept in the
/// given order (so vertex and edge indices are the caller's). Throws InvalidInput, naming the
/// vertex, if a coordinate is not finite, two consecutive vertices coincide, a corner turns
/// clockwise or is straight (collinear), the outline winds more than once, there are fewer than
/// 3 or more than kMaxPolygonVertices vertices, or the radius is negative or not finite.
[[nodiscard]] Polygon make_convex_polygon(std::span<const Vec2> vertices, float radius = 0.0f);

/// Axis-aligned box with half extents `half` centred on the local origin; vertex 0 is the
/// lower-left corner, counter-clockwise. Throws InvalidInput if an extent is not finite or <= 0.
[[nodiscard]] Polygon make_box(Vec2 half, float radius = 0.0f);

/// Box with half extents `half`, rotated by `angle` (radians, counter-clockwise) about its
/// centre, then centred on `center` (local space). Throws as `make_box`.
[[nodiscard]] Polygon make_box(Vec2 half, Vec2 center, float angle, float radius = 0.0f);

/// Bounding box of the polygon (including its radius) placed by `xf`, world space.
[[nodiscard]] Aabb compute_aabb(const Polygon& polygon, const Transform& xf) noexcept;

/// Signed area of the polygon's core (positive: counter-clockwise). Shoelace formula.
[[nodiscard]] float signed_area(std::span<const Vec2> vertices) noexcept;

}  // namespace collide
