// The overlap polygon of two convex polygons by half-plane clipping (the lesson's "convex/convex
// polygon intersection"; Sutherland & Hodgman, "Reentrant Polygon Clipping", 1974; Ericson 8.3.4).
//
// A convex polygon is the intersection of its edges' inner half-planes, so the overlap of A and
// B is A clipped by each of B's edge half-planes in turn. One clip keeps the vertices inside
// the half-plane and inserts the points where the outline crosses its line; a convex outline
// crosses a line at most twice, so each clip adds at most one vertex and the result has at most
// n + m. Everything happens in A's local frame (B is moved there once), on the stack.

#include <collide/narrow/intersect.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <string>

namespace collide {
namespace {

struct Outline {
  std::array<Vec2, kMaxOverlapVertices> v;
  int count = 0;

  /// Append a vertex; a clip that would overflow (possible only through rounding on nearly
  /// collinear outlines) drops the extra vertex, which moves the outline by rounding error.
  void push(Vec2 p) noexcept {
    if (count < kMaxOverlapVertices) v[count++] = p;
  }
};

/// `in` clipped to the half-plane normal . (x - point) <= 0, written to `out`.
void clip(const Outline& in, Vec2 normal, Vec2 point, Outline& out) noexcept {
  out.count = 0;
  if (in.count == 0) return;
  Vec2 cur = in.v[in.count - 1];
  float d_cur = dot(normal, cur - point);
  for (int k = 0; k < in.count; ++k) {
    const Vec2 nxt = in.v[k];
    const float d_nxt = dot(normal, nxt - point);
    // The edge cur -> nxt crosses the line strictly: insert the crossing.
    if ((d_cur < 0.0f && d_nxt > 0.0f) || (d_cur > 0.0f && d_nxt < 0.0f)) {
      out.push(cur + (d_cur / (d_cur - d_nxt)) * (nxt - cur));
    }
    if (d_nxt <= 0.0f) out.push(nxt);
    cur = nxt;
    d_cur = d_nxt;
  }
}

/// Largest side of the bounding box of `count` points.
float extent(const Vec2* v, int count) noexcept {
  Vec2 lo = v[0];
  Vec2 hi = v[0];
  for (int k = 1; k < count; ++k) {
    lo = glm::min(lo, v[k]);
    hi = glm::max(hi, v[k]);
  }
  return std::max(hi.x - lo.x, hi.y - lo.y);
}

void reject_rounded(const Polygon& p, const char* name) {
  if (p.radius != 0.0f) {
    throw InvalidInput(std::string("intersect: polygon ") + name + " radius is " +
                       std::to_string(p.radius) +
                       "; the overlap of rounded polygons is not a polygon (use radius 0)");
  }
}

}  // namespace

OverlapPolygon intersect(const Polygon& a, const Transform& xa, const Polygon& b,
                         const Transform& xb) {
  reject_rounded(a, "a");
  reject_rounded(b, "b");
  const Transform b_in_a = inv_mul(xa, xb);

  Outline buffers[2];
  Outline* in = &buffers[0];
  Outline* out = &buffers[1];
  std::copy(a.vertices.begin(), a.vertices.begin() + a.count, in->v.begin());
  in->count = a.count;
  for (int j = 0; j < b.count && in->count > 0; ++j) {
    clip(*in, rotate(b_in_a.q, b.normals[j]), transform_point(b_in_a, b.vertices[j]), *out);
    std::swap(in, out);
  }

  OverlapPolygon result;
  if (in->count < 3) return result;
  // Tolerances scale with the inputs' size (the larger polygon's bounding box): drop repeated
  // vertices (a clip line through a vertex) within the weld tolerance, and measure the area
  // about the first vertex (keeps precision).
  const float size =
      std::max(extent(a.vertices.data(), a.count), extent(b.vertices.data(), b.count));
  const float weld2 = (kWeldTolerance * size) * (kWeldTolerance * size);
  Outline& poly = *out;
  poly.count = 0;
  for (int k = 0; k < in->count; ++k) {
    const Vec2 p = in->v[k];
    if (poly.count > 0 && distance_squared(poly.v[poly.count - 1], p) <= weld2) continue;
    poly.push(p);
  }
  while (poly.count > 1 && distance_squared(poly.v[poly.count - 1], poly.v[0]) <= weld2) {
    --poly.count;
  }
  if (poly.count < 3) return result;

  const Vec2 origin = poly.v[0];
  float area = 0.0f;
  Vec2 c{0.0f, 0.0f};
  for (int k = 1; k + 1 < poly.count; ++k) {
    const Vec2 e1 = poly.v[k] - origin;
    const Vec2 e2 = poly.v[k + 1] - origin;
    const float tri = 0.5f * cross(e1, e2);
    area += tri;
    c += tri * (e1 + e2) * (1.0f / 3.0f);
  }
  // Touching along an edge or at a point leaves a sliver of rounding-error area: empty.
  if (!(area > kDegenerateAreaTolerance * size * size)) return result;

  result.count = poly.count;
  for (int k = 0; k < poly.count; ++k) result.vertices[k] = transform_point(xa, poly.v[k]);
  result.area = area;
  result.centroid = transform_point(xa, origin + c * (1.0f / area));
  return result;
}

}  // namespace collide
