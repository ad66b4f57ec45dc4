#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>
#include <collide/narrow/minkowski.hpp>

#include "touching_feature.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace collide {
namespace {

/// Diagonal of the core's local bounding box.
float core_size(const Polygon& p) {
  const Aabb box = compute_aabb(p, Transform{});
  return distance(box.min, box.max);
}

}  // namespace

// The lesson's construction, literally: build A - B, cast the ray from the origin along
// vb - va into it, and read the time of first touch off the ray's entry. Done in A's frame (B
// placed by xa^-1 xb) so far-away shapes keep their precision.
ShapeCastResult shape_cast_minkowski(const Polygon& a, const Transform& xa, Vec2 va,
                                     const Polygon& b, const Transform& xb, Vec2 vb) {
  check_cast_input(xa, va, xb, vb);
  const Transform b_in_a = inv_mul(xa, xb);
  const MinkowskiPolygon difference = minkowski_difference(a, Transform{}, b, b_in_a);
  if (difference.vertices.size() > static_cast<size_t>(kMaxPolygonVertices)) {
    throw InvalidInput("shape_cast_minkowski: A - B has " +
                       std::to_string(difference.vertices.size()) +
                       " vertices, more than kMaxPolygonVertices");
  }
  const Vec2 va_local = inv_rotate(xa.q, va);
  const Vec2 vb_local = inv_rotate(xa.q, vb);

  ShapeCastResult result;
  if (difference.contains_origin()) {
    result.hit = true;
    result.fraction = 0.0f;
    result.status = QueryStatus::overlapped;
    return result;
  }
  const Polygon d = make_polygon(difference.vertices, difference.radius);
  const RayHit entry = raycast(d, Transform{}, Ray{{0.0f, 0.0f}, vb_local - va_local});
  if (!entry.hit) return result;  // separated, t = 1

  // The outward normal of A - B where the ray enters is the normal from A to B (A's support
  // along n minus B's support along -n is that boundary point).
  const Vec2 n = entry.normal;
  const float t = entry.fraction;
  const float tie = detail::kFeatureTieTolerance * std::max(core_size(a), core_size(b));
  const detail::TouchingFeature fa = detail::touching_feature(
      a.count, [&](int i) { return a.vertices[i] + t * va_local; }, n, 1.0f, tie);
  const detail::TouchingFeature fb = detail::touching_feature(
      b.count, [&](int i) { return transform_point(b_in_a, b.vertices[i]) + t * vb_local; }, n,
      -1.0f, tie);
  result.hit = true;
  result.fraction = t;
  result.status = t > 0.0f ? QueryStatus::hit : QueryStatus::overlapped;
  result.normal = rotate(xa.q, n);
  result.point = transform_point(xa, detail::touching_point(fa, a.radius, fb, b.radius, n));
  return result;
}

}  // namespace collide
