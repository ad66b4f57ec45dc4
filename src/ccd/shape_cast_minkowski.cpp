#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>
#include <collide/narrow/minkowski.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace collide {
namespace {

/// Fraction of the shapes' size within which two vertices count as equally far along the
/// normal: they then form the touching edge rather than a touching vertex.
constexpr float kFeatureTieTolerance = 1e-4f;

/// Where along the tangent `u` and the normal `n` the touching features of A and B lie: the
/// core vertices farthest along n on A and against n on B, each set's extent along u.
struct TouchingFeature {
  float height = 0.0f;  ///< along n: the core's extreme
  float lo = 0.0f;      ///< along u: the feature's extent
  float hi = 0.0f;
};

/// The vertices of `core` (moved by `offset`) extreme along `sign * n`, within `tie`.
TouchingFeature touching_feature(const Vec2* core, int count, const Transform& xf, Vec2 offset,
                                 Vec2 n, float sign, float tie) {
  float best = -INFINITY;
  for (int i = 0; i < count; ++i) {
    best = std::max(best, sign * dot(transform_point(xf, core[i]) + offset, n));
  }
  const Vec2 u = left_perp(n);
  TouchingFeature f{sign * best, INFINITY, -INFINITY};
  for (int i = 0; i < count; ++i) {
    const Vec2 p = transform_point(xf, core[i]) + offset;
    if (sign * dot(p, n) >= best - tie) {
      f.lo = std::min(f.lo, dot(p, u));
      f.hi = std::max(f.hi, dot(p, u));
    }
  }
  return f;
}

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
  const float tie = kFeatureTieTolerance * std::max(core_size(a), core_size(b));
  const TouchingFeature fa =
      touching_feature(a.vertices.data(), a.count, Transform{}, t * va_local, n, 1.0f, tie);
  const TouchingFeature fb =
      touching_feature(b.vertices.data(), b.count, b_in_a, t * vb_local, n, -1.0f, tie);
  // The middle of the overlap of the two features along the tangent (vertex against edge: the
  // vertex; edge against edge: the middle of the shared part), midway between the surfaces.
  const float lo = std::max(fa.lo, fb.lo);
  const float hi = std::min(fa.hi, fb.hi);
  const float along = 0.5f * (lo + hi);
  const float across = 0.5f * ((fa.height + a.radius) + (fb.height - b.radius));
  result.hit = true;
  result.fraction = t;
  result.status = t > 0.0f ? QueryStatus::hit : QueryStatus::overlapped;
  result.normal = rotate(xa.q, n);
  result.point = transform_point(xa, along * left_perp(n) + across * n);
  return result;
}

}  // namespace collide
