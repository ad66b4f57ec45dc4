#include <collide/shape/polygon.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace collide {
namespace {

/// make_box keeps its exact normals while each rounded edge runs along its normal's
/// perpendicular within this (the tangent of the angle between them); beyond it the edge's own
/// direction gives its normal.
constexpr float kBoxEdgeTurnTolerance = 0.1f;

void check_radius(float radius, const char* what) {
  if (!std::isfinite(radius)) throw InvalidInput(std::string(what) + " radius: not finite");
  if (radius < 0.0f) {
    throw InvalidInput(std::string(what) + " radius: negative (" + std::to_string(radius) + ")");
  }
}

void check_points_finite(std::span<const Vec2> points, const char* what) {
  for (size_t i = 0; i < points.size(); ++i) {
    if (!is_finite(points[i])) {
      throw InvalidInput(std::string(what) + " vertex " + std::to_string(i) + ": not finite");
    }
  }
}

/// Largest coordinate magnitude span of the point set: the size that tolerances scale with.
float extent_of(std::span<const Vec2> points) {
  Vec2 lo = points[0];
  Vec2 hi = points[0];
  for (Vec2 p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return std::max(hi.x - lo.x, hi.y - lo.y);
}

/// The unit normal to the right of `edge`. Its squared length underflows below float's normal
/// range for edges shorter than about 1e-19 (a polygon of 1e-21 had an edge whose normal came
/// out zero, and contact then gave a zero normal) and overflows above about 1e19: those edges
/// are first scaled to a largest component of 1. Others take the plain formula, so ordinary
/// polygons keep their normals to the bit. Zero for an edge whose largest component is itself
/// denormal (below about 1.2e-38: the scale 1 / largest overflows), so callers keep such edges
/// out: make_convex_polygon refuses them as repeated vertices, make_box keeps the axis.
Vec2 edge_normal(Vec2 edge) {
  const float length2 = length_squared(edge);
  if (length2 >= std::numeric_limits<float>::min() && length2 <= std::numeric_limits<float>::max()) {
    return normalize_or_zero(right_perp(edge));
  }
  const float largest = std::max(std::abs(edge.x), std::abs(edge.y));
  return normalize_or_zero(right_perp(edge * (1.0f / largest)));
}

/// Fill normals and centroid of a polygon whose vertices and count are set and valid.
void finish(Polygon& poly) {
  const int n = poly.count;
  for (int i = 0; i < n; ++i) {
    poly.normals[i] = edge_normal(poly.vertices[(i + 1) % n] - poly.vertices[i]);
  }
  // Area centroid relative to vertex 0 (keeps precision far from the origin).
  const Vec2 origin = poly.vertices[0];
  float area = 0.0f;
  Vec2 c{0.0f, 0.0f};
  for (int i = 1; i + 1 < n; ++i) {
    const Vec2 e1 = poly.vertices[i] - origin;
    const Vec2 e2 = poly.vertices[i + 1] - origin;
    const float a = 0.5f * cross(e1, e2);
    c += a * (e1 + e2) * (1.0f / 3.0f);
    area += a;
  }
  poly.centroid = origin + c * (1.0f / area);
}

}  // namespace

void PolygonPoints::resize(int count) {
  COLLIDE_ASSERT(count >= 0 && count <= kMaxPolygonVertices, "polygon point count out of range");
  if (count <= capacity()) return;
  auto block = std::make_unique_for_overwrite<Vec2[]>(kMaxPolygonVertices);
  std::memcpy(static_cast<void*>(block.get()), static_cast<const void*>(inline_), sizeof(inline_));
  heap_ = std::move(block);
}

void PolygonPoints::copy_from(const PolygonPoints& other) {
  if (!other.heap_) {
    heap_.reset();
  } else if (!heap_) {
    heap_ = std::make_unique_for_overwrite<Vec2[]>(kMaxPolygonVertices);
  }
  // Raw bytes: slots past the polygon's count may be unset.
  std::memcpy(static_cast<void*>(data()), static_cast<const void*>(other.data()),
              static_cast<size_t>(other.capacity()) * sizeof(Vec2));
}

float signed_area(std::span<const Vec2> vertices) noexcept {
  if (vertices.size() < 3) return 0.0f;
  const Vec2 origin = vertices[0];
  float twice = 0.0f;
  for (size_t i = 1; i + 1 < vertices.size(); ++i) {
    twice += cross(vertices[i] - origin, vertices[i + 1] - origin);
  }
  return 0.5f * twice;
}

Polygon make_polygon(std::span<const Vec2> points, float radius) {
  check_radius(radius, "polygon");
  check_points_finite(points, "polygon");
  if (points.size() < 3) {
    throw InvalidInput("polygon: needs at least 3 points, got " + std::to_string(points.size()));
  }
  // Andrew's monotone chain on a sorted copy. Runs once per shape, never inside a query, so a
  // heap copy is fine here.
  std::vector<Vec2> sorted(points.begin(), points.end());
  std::sort(sorted.begin(), sorted.end(),
            [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  const float size = extent_of(sorted);
  const float weld = kWeldTolerance * size;
  // Drop near-duplicates (welded by tolerance relative to the set's size).
  std::vector<Vec2> unique;
  unique.reserve(sorted.size());
  for (Vec2 p : sorted) {
    bool dup = false;
    for (auto it = unique.rbegin(); it != unique.rend() && p.x - it->x <= weld; ++it) {
      if (distance_squared(p, *it) <= weld * weld) {
        dup = true;
        break;
      }
    }
    if (!dup) unique.push_back(p);
  }
  if (unique.size() < 3) {
    throw InvalidInput("polygon: fewer than 3 distinct points (" + std::to_string(unique.size()) +
                       ")");
  }
  // A turn counts as convex only if it bends by more than the area tolerance: collinear and
  // nearly collinear points are dropped.
  const float area_tol = kDegenerateAreaTolerance * size * size;
  std::vector<Vec2> hull(2 * unique.size());
  size_t k = 0;
  for (size_t i = 0; i < unique.size(); ++i) {  // lower hull
    while (k >= 2 && cross(hull[k - 1] - hull[k - 2], unique[i] - hull[k - 2]) <= area_tol) --k;
    hull[k++] = unique[i];
  }
  for (size_t i = unique.size() - 1, lower = k + 1; i-- > 0;) {  // upper hull
    while (k >= lower && cross(hull[k - 1] - hull[k - 2], unique[i] - hull[k - 2]) <= area_tol) {
      --k;
    }
    hull[k++] = unique[i];
  }
  hull.resize(k - 1);  // last point repeats the first
  if (hull.size() < 3) {
    throw InvalidInput("polygon: points are collinear (zero area)");
  }
  if (hull.size() > static_cast<size_t>(kMaxPolygonVertices)) {
    throw InvalidInput("polygon: convex hull has " + std::to_string(hull.size()) +
                       " vertices, more than kMaxPolygonVertices (" +
                       std::to_string(kMaxPolygonVertices) + ")");
  }
  Polygon poly;
  poly.set_count(static_cast<int>(hull.size()));
  std::copy(hull.begin(), hull.end(), poly.vertices.begin());
  poly.radius = radius;
  finish(poly);
  return poly;
}

Polygon make_convex_polygon(std::span<const Vec2> vertices, float radius) {
  check_radius(radius, "polygon");
  check_points_finite(vertices, "polygon");
  const size_t n = vertices.size();
  if (n < 3) {
    throw InvalidInput("polygon: needs at least 3 vertices, got " + std::to_string(n));
  }
  if (n > static_cast<size_t>(kMaxPolygonVertices)) {
    throw InvalidInput("polygon: " + std::to_string(n) +
                       " vertices, more than kMaxPolygonVertices (" +
                       std::to_string(kMaxPolygonVertices) + ")");
  }
  const float size = extent_of(vertices);
  const float weld = kWeldTolerance * size;
  const float area_tol = kDegenerateAreaTolerance * size * size;
  for (size_t i = 0; i < n; ++i) {
    if (distance_squared(vertices[i], vertices[(i + 1) % n]) <= weld * weld) {
      throw InvalidInput("polygon vertex " + std::to_string((i + 1) % n) +
                         ": repeats vertex " + std::to_string(i));
    }
  }
  // Every corner must turn left (strictly): convex and counter-clockwise.
  for (size_t i = 0; i < n; ++i) {
    const Vec2 prev = vertices[(i + n - 1) % n];
    const Vec2 cur = vertices[i];
    const Vec2 next = vertices[(i + 1) % n];
    const float turn = cross(cur - prev, next - cur);
    if (turn <= area_tol) {
      const bool straight = std::fabs(turn) <= area_tol;
      throw InvalidInput("polygon vertex " + std::to_string(i) +
                         (straight ? ": collinear with its neighbours (not strictly convex)"
                                   : ": turns clockwise (polygon must be convex and "
                                     "counter-clockwise)"));
    }
  }
  // Left turns everywhere can still wind twice around (a star); the total turning is then
  // 4 pi. Convex and simple iff the edge directions' angles sum to exactly one turn.
  double turning = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 e0 = vertices[(i + 1) % n] - vertices[i];
    const Vec2 e1 = vertices[(i + 2) % n] - vertices[(i + 1) % n];
    turning += std::atan2(static_cast<double>(cross(e0, e1)), static_cast<double>(dot(e0, e1)));
  }
  if (turning > 3.0 * 3.14159265358979) {
    throw InvalidInput("polygon: outline winds around more than once (self-intersecting)");
  }
  Polygon poly;
  poly.set_count(static_cast<int>(n));
  std::copy(vertices.begin(), vertices.end(), poly.vertices.begin());
  poly.radius = radius;
  finish(poly);
  return poly;
}

Polygon make_box(Vec2 half, float radius) {
  return make_box(half, Vec2{0.0f, 0.0f}, 0.0f, radius);
}

Polygon make_box(Vec2 half, Vec2 center, float angle, float radius) {
  if (!is_finite(half) || !is_finite(center) || !std::isfinite(angle)) {
    throw InvalidInput("box: half extents, centre and angle must be finite");
  }
  if (!(half.x > 0.0f && half.y > 0.0f)) {
    throw InvalidInput("box half: extents must be > 0");
  }
  check_radius(radius, "box");
  const Transform xf = Transform::from(center, angle);
  Polygon poly;
  poly.set_count(4);
  poly.vertices[0] = transform_point(xf, {-half.x, -half.y});
  poly.vertices[1] = transform_point(xf, {half.x, -half.y});
  poly.vertices[2] = transform_point(xf, {half.x, half.y});
  poly.vertices[3] = transform_point(xf, {-half.x, half.y});
  poly.normals[0] = rotate(xf.q, {0.0f, -1.0f});
  poly.normals[1] = rotate(xf.q, {1.0f, 0.0f});
  poly.normals[2] = rotate(xf.q, {0.0f, 1.0f});
  poly.normals[3] = rotate(xf.q, {-1.0f, 0.0f});
  poly.centroid = center;
  poly.radius = radius;
  // Far from the origin, extents near the float step there no longer make the box once its
  // corners are rounded: an edge turns away from its normal (fuzz_shapes: a box 1.5e-37 wide at
  // x = 2.16e8, whose corners fell onto two points of a vertical line while its normals stayed
  // the rotated axes, so the closest-feature walk of `distance` followed the normal of an edge
  // that was not there). Such an edge takes the normal of the edge it has become. An edge that
  // vanished (corners rounded onto each other, or too close to give a direction: a box of no
  // height) or overflowed keeps its axis, as every other box keeps its exact normals.
  for (int i = 0; i < 4; ++i) {
    const Vec2 edge = poly.vertices[next_vertex(i, 4)] - poly.vertices[i];
    if (!is_finite(edge) || !(length_squared(edge) >= kMinDirectionLengthSquared)) continue;
    const float along = dot(edge, left_perp(poly.normals[i]));
    if (along > 0.0f && std::abs(dot(edge, poly.normals[i])) <= kBoxEdgeTurnTolerance * along) continue;
    poly.normals[i] = edge_normal(edge);
  }
  return poly;
}

Aabb compute_aabb(const Polygon& polygon, const Transform& xf) noexcept {
  Vec2 lo = transform_point(xf, polygon.vertices[0]);
  Vec2 hi = lo;
  for (int i = 1; i < polygon.count; ++i) {
    const Vec2 v = transform_point(xf, polygon.vertices[i]);
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const Vec2 r{polygon.radius, polygon.radius};
  return {lo - r, hi + r};
}

}  // namespace collide
