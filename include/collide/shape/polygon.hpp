#pragma once
/// @file
/// Convex polygons with an optional rounding radius. Up to 8 vertices are stored inline; larger
/// polygons keep their points in one heap block made when they are built. Queries never
/// allocate.

#include <collide/core/aabb.hpp>
#include <collide/core/transform.hpp>

#include <memory>
#include <span>

namespace collide {

/// Most vertices a Polygon holds. Queries keep every temporary on the stack at this size.
inline constexpr int kMaxPolygonVertices = 64;

/// Vertices a Polygon keeps inline; polygons with more keep their points in one heap block,
/// allocated when the polygon is built or copied (never by a query). Box2D v3's limit (8), so
/// the polygons games build most (boxes, wedges, octagons) never touch the heap.
inline constexpr int kInlinePolygonVertices = 8;

/// The points of a Polygon (vertices or edge normals): kInlinePolygonVertices inline, or all
/// kMaxPolygonVertices slots in a heap block. Indexed like an array; holds no count of its own
/// (the polygon's `count` says how many slots are meaningful). The block pointer sits just
/// before the inline slots, so a small polygon's query reads both from the same cache line.
class PolygonPoints {
 public:
  PolygonPoints() noexcept {}  // NOLINT: inline slots deliberately left unset (no 64-byte fill)
  PolygonPoints(const PolygonPoints& other) { copy_from(other); }
  PolygonPoints(PolygonPoints&& other) noexcept = default;
  PolygonPoints& operator=(const PolygonPoints& other) {
    if (this != &other) copy_from(other);
    return *this;
  }
  PolygonPoints& operator=(PolygonPoints&& other) noexcept = default;
  ~PolygonPoints() = default;

  /// Makes room for `count` points (0..kMaxPolygonVertices), keeping the points held. Allocates
  /// (once, kMaxPolygonVertices slots) only above kInlinePolygonVertices.
  void resize(int count);

  /// Slots held: kInlinePolygonVertices, or kMaxPolygonVertices once on the heap.
  [[nodiscard]] int capacity() const noexcept {
    return heap_ ? kMaxPolygonVertices : kInlinePolygonVertices;
  }
  [[nodiscard]] const Vec2* data() const noexcept { return heap_ ? heap_.get() : inline_; }
  [[nodiscard]] Vec2* data() noexcept { return heap_ ? heap_.get() : inline_; }
  [[nodiscard]] const Vec2& operator[](size_t i) const noexcept { return data()[i]; }
  [[nodiscard]] Vec2& operator[](size_t i) noexcept { return data()[i]; }
  [[nodiscard]] const Vec2* begin() const noexcept { return data(); }
  [[nodiscard]] Vec2* begin() noexcept { return data(); }

 private:
  void copy_from(const PolygonPoints& other);

  std::unique_ptr<Vec2[]> heap_;
  Vec2 inline_[kInlinePolygonVertices];  // NOLINT: C array, left unset until written
};

/// A convex polygon, counter-clockwise, in local space, optionally rounded: the solid set of
/// points within `radius` of the convex hull of `vertices`. Edge i runs from vertex i to vertex
/// i + 1 (mod count) and `normals[i]` is its unit outward normal.
///
/// Build polygons with `make_polygon`, `make_convex_polygon` or `make_box`, which establish the
/// invariants (3..kMaxPolygonVertices distinct vertices, strictly convex, counter-clockwise,
/// finite); treat the fields as read-only afterwards. Inside collide, capsules and segments are
/// also seen as 2-vertex polygons (count 2), which public constructors never produce. Code that
/// builds a polygon by hand calls `set_count` before writing its points (needed above
/// kInlinePolygonVertices; the 2-vertex polygons set `count` directly).
///
/// Size: 192 bytes (up to kInlinePolygonVertices vertices and normals inline, more on the
/// heap), a sixth of the 1 KiB it took with 64 slots inline: 1024 polygons fit in 192 KiB of
/// cache. Aligned to a cache line: a polygon of up to 4 vertices has its header and vertices in
/// its first line and its normals in the second; up to 8, three lines.
struct alignas(64) Polygon {
  // Small fields first: a query on a small polygon then touches the count, the radius and the
  // first vertices in the same cache line.
  int count = 0;                  ///< number of vertices
  float radius = 0.0f;            ///< rounding radius, >= 0
  Vec2 centroid{0.0f, 0.0f};      ///< area centroid of the core, local space
  PolygonPoints vertices;         ///< local space, counter-clockwise; `count` of them
  PolygonPoints normals;          ///< unit outward normal of edge i; `count` of them

  /// Sets `count` (0..kMaxPolygonVertices) and makes room for that many vertices and normals;
  /// allocates only above kInlinePolygonVertices.
  void set_count(int n) {
    vertices.resize(n);
    normals.resize(n);
    count = n;
  }

  /// Vertex i wrapped modulo count.
  [[nodiscard]] Vec2 vertex(int i) const noexcept { return vertices[static_cast<size_t>(i % count)]; }
};

/// Index of the vertex after vertex `i` of a closed outline of `n` vertices (counter-clockwise:
/// edge i runs from vertex i to vertex next_vertex(i, n)), wrapping to 0.
[[nodiscard]] constexpr int next_vertex(int i, int n) noexcept { return i + 1 == n ? 0 : i + 1; }
/// Index of the vertex before vertex `i` of a closed outline of `n` vertices, wrapping to n - 1.
[[nodiscard]] constexpr int previous_vertex(int i, int n) noexcept {
  return i == 0 ? n - 1 : i - 1;
}

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
/// centre, then centred on `center` (local space). Throws as `make_box`. Far from the origin,
/// where extents near the float step there round its corners onto a different outline, an edge
/// turned markedly from its axis (by more than about 0.1 rad) takes its own direction's normal.
[[nodiscard]] Polygon make_box(Vec2 half, Vec2 center, float angle, float radius = 0.0f);

/// Bounding box of the polygon (including its radius) placed by `xf`, world space.
[[nodiscard]] Aabb compute_aabb(const Polygon& polygon, const Transform& xf) noexcept;

/// Signed area of the polygon's core (positive: counter-clockwise). Shoelace formula.
[[nodiscard]] float signed_area(std::span<const Vec2> vertices) noexcept;

}  // namespace collide
