// Explicit Minkowski sum and difference of two convex polygons (the lesson's "Minkowski Sum").
//
// The boundary of A + B is made of A's and B's edges sorted by direction: start at the sum of
// both lowest (then leftmost) vertices, which is the lowest vertex of A + B, and repeatedly take
// whichever of the two current edges turns least (de Berg et al., Computational Geometry,
// 3rd ed., 13.3). Edges of equal direction are taken together, so the result has no collinear
// vertices. A - B is A + (-B): negating a counter-clockwise polygon is a half turn, which keeps
// it counter-clockwise.

#include <collide/narrow/minkowski.hpp>

#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace collide {
namespace {

/// A placed polygon, on the stack: vertex i is at origin + rel[i], world space. Edge directions
/// and the lowest vertex come from `rel`, rotated but not yet moved: far from the world origin
/// they keep full precision, so parallel edges are still recognised as parallel.
struct PlacedVertices {
  std::array<Vec2, kMaxPolygonVertices> rel;
  Vec2 origin{0.0f, 0.0f};
  int count = 0;
};

PlacedVertices place(const Polygon& poly, const Transform& xf, float sign) noexcept {
  PlacedVertices out;
  out.count = poly.count;
  out.origin = sign * xf.p;
  for (int i = 0; i < poly.count; ++i) out.rel[i] = sign * rotate(xf.q, poly.vertices[i]);
  return out;
}

/// Index of the lowest vertex, the leftmost among equally low ones.
int lowest(const PlacedVertices& p) noexcept {
  int best = 0;
  for (int i = 1; i < p.count; ++i) {
    const Vec2 v = p.rel[i];
    const Vec2 b = p.rel[best];
    if (v.y < b.y || (v.y == b.y && v.x < b.x)) best = i;
  }
  return best;
}

MinkowskiPolygon merge(const PlacedVertices& a, const PlacedVertices& b, float radius) {
  const int n = a.count;
  const int m = b.count;
  const int i0 = lowest(a);
  const int j0 = lowest(b);
  auto va = [&](int k) { return a.rel[(i0 + k) % n]; };
  auto vb = [&](int k) { return b.rel[(j0 + k) % m]; };
  const Vec2 origin = a.origin + b.origin;
  MinkowskiPolygon out;
  out.radius = radius;
  out.vertices.reserve(static_cast<size_t>(n + m));
  // Both sequences start at their lowest vertex, so edge directions increase from [0, pi)
  // through one full turn; consecutive candidates differ by less than pi, where the sign of
  // the cross product orders them.
  int i = 0;
  int j = 0;
  while (i < n || j < m) {
    out.vertices.push_back(origin + (va(i) + vb(j)));
    const Vec2 ea = va(i + 1) - va(i);
    const Vec2 eb = vb(j + 1) - vb(j);
    if (i == n) {
      ++j;
    } else if (j == m) {
      ++i;
    } else {
      const float turn = cross(ea, eb);  // > 0: B's edge turns further, take A's first
      // Same direction within kParallelTolerance (sine of the angle): one merged edge.
      const bool parallel =
          std::fabs(turn) <= kParallelTolerance * length(ea) * length(eb) && dot(ea, eb) > 0.0f;
      if (parallel) {
        ++i;
        ++j;
      } else if (turn > 0.0f) {
        ++i;
      } else {
        ++j;
      }
    }
  }
  return out;
}

}  // namespace

float MinkowskiPolygon::signed_distance_to_origin() const noexcept {
  // Inside: minus the distance to the nearest edge line (the largest separation). Outside: the
  // distance to the nearest edge segment (Ericson 5.1.2 per edge). Then the rounding radius.
  const size_t n = vertices.size();
  if (n == 0) return 0.0f;
  float max_sep = -INFINITY;
  float min_dist2 = INFINITY;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 v = vertices[i];
    const Vec2 e = vertices[i + 1 < n ? i + 1 : 0] - v;
    const float ee = length_squared(e);
    if (!(ee > 0.0f)) {  // one vertex (a degenerate input): the distance to that point
      min_dist2 = std::min(min_dist2, length_squared(v));
      continue;
    }
    max_sep = std::max(max_sep, cross(e, v) / std::sqrt(ee));  // n . (0 - v), n = right_perp(e)
    const float s = std::clamp(dot(-v, e) / ee, 0.0f, 1.0f);
    min_dist2 = std::min(min_dist2, length_squared(v + s * e));
  }
  const float core = max_sep <= 0.0f && n >= 3 ? max_sep : std::sqrt(min_dist2);
  return core - radius;
}

MinkowskiPolygon minkowski_sum(const Polygon& a, const Transform& xa, const Polygon& b,
                               const Transform& xb) {
  return merge(place(a, xa, 1.0f), place(b, xb, 1.0f), a.radius + b.radius);
}

MinkowskiPolygon minkowski_difference(const Polygon& a, const Transform& xa, const Polygon& b,
                                      const Transform& xb) {
  return merge(place(a, xa, 1.0f), place(b, xb, -1.0f), a.radius + b.radius);
}

}  // namespace collide
