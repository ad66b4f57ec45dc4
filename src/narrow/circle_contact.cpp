// Contacts with a circle: circle-circle analytically, polygon-circle by the Voronoi region of
// the circle's centre. Both give one point midway between the surfaces.

#include <algorithm>
#include <array>
#include <cmath>
#include <collide/core/error.hpp>
#include <collide/core/lanes.hpp>
#include <collide/narrow/contact.hpp>
#include <limits>
#include <type_traits>

#include "contact_routines.hpp"
#include "point_region.hpp"

namespace collide::detail {
namespace {

constexpr ContactId circle_id(int index_a, FeatureType type_a) noexcept {
  return {static_cast<std::uint8_t>(index_a), 0, type_a, FeatureType::face};
}

}  // namespace

// The centres are apart by d; the circles touch when |d| <= ra + rb. The normal is d / |d| (for
// coincident centres any direction is right: world +x). A's surface point is ca + ra n, B's is
// cb - rb n. Relative positions are formed before anything is added to a world coordinate.
Manifold contact_circles(const Circle& a, const Transform& xa, const Circle& b,
                         const Transform& xb) noexcept {
  const Vec2 ca = rotate(xa.q, a.center);  // relative to xa.p
  const Vec2 d = (xb.p - xa.p) + rotate(xb.q, b.center) - ca;
  const float radius = a.radius + b.radius;
  const float dist2 = length_squared(d);
  Manifold m;  // the one object returned on every path: built in the caller's slot
  if (!(dist2 <= radius * radius)) return m;
  const float dist = std::sqrt(dist2);
  const Vec2 n = dist > 0.0f ? d * (1.0f / dist) : Vec2{1.0f, 0.0f};
  m.normal = n;
  // Midway between ca + ra n and ca + dist n - rb n.
  m.points[0] = {xa.p + (ca + (0.5f * (a.radius + dist - b.radius)) * n), radius - dist,
                 circle_id(0, FeatureType::face)};
  m.count = 1;
  return m;
}

// In A's frame, the edge of greatest separation s = dot(n_i, c - v_i) of the centre c is found
// first (early exit once s > ra + rb). If c is outside that edge, its Voronoi region is one of
// the edge's end vertices or the edge itself, told apart by the projections of c on the edge
// from each end (Ericson 5.2.7). If c is inside the core, the edge of greatest separation is the
// shortest way out. A 2-vertex polygon (capsule, segment) has no inside: its two edges are the
// two sides of one segment, so its end regions are always tested.
Manifold contact_polygon_circle(const Polygon& a, const Transform& xa, const Circle& b,
                                const Transform& xb) noexcept {
  // B's centre in A's frame; the world offset is formed first, so far from the origin only
  // small numbers are rotated.
  const Vec2 c = inv_rotate(xa.q, (xb.p - xa.p) + rotate(xb.q, b.center));
  const float radius = a.radius + b.radius;
  Manifold m;  // the one object returned on every path: built in the caller's slot
  int edge = 0;
  float separation = -std::numeric_limits<float>::infinity();
  for (int i = 0; i < a.count; ++i) {
    const float s = dot(a.normals[i], c - a.vertices[i]);
    if (s > radius) return m;  // a separating axis
    // The running maximum by selects, not a branch: which edge leads is a coin toss for pairs
    // met in an order the branch predictor has not learnt (bench_narrow_contact, shuffled
    // circle-polygon pairs, AMD EPYC: 33.4 -> 23.1 ns a pair; replayed in a learnt order
    // 7.9 -> 9.9 ns, the selects' chain).
    edge = s > separation ? i : edge;
    separation = s > separation ? s : separation;
  }
  const int next = next_vertex(edge, a.count);
  const Vec2 v1 = a.vertices[edge];
  const Vec2 v2 = a.vertices[next];

  Vec2 n = a.normals[edge];
  Vec2 core_point = c - separation * n;  // face region: c projected on the edge
  float distance = separation;           // of c from A's core, signed
  ContactId id = circle_id(edge, FeatureType::edge);
  if (separation > 0.0f || a.count == 2) {
    const int region = edge_end_region(a, edge, next, c);
    const bool at_v1 = region == edge;
    const bool at_v2 = region == next;
    if (at_v1 || at_v2) {
      const Vec2 v = at_v1 ? v1 : v2;
      const Vec2 d = c - v;
      const float dist2 = length_squared(d);
      if (!(dist2 <= radius * radius)) return m;
      const float dist = std::sqrt(dist2);
      if (dist > 0.0f) {  // else c sits on the vertex: the face normal serves
        n = d * (1.0f / dist);
        core_point = v;
        distance = dist;
        id = circle_id(at_v1 ? edge : next, FeatureType::vertex);
      }
    }
  }
  // A's surface point core_point + ra n, B's c - rb n; c = core_point + distance n.
  const Vec2 mid = core_point + (0.5f * (a.radius + distance - b.radius)) * n;
  m.normal = rotate(xa.q, n);
  m.points[0] = {transform_point(xa, mid), radius - distance, id};
  m.count = 1;
  return m;
}

namespace {

using simd::LaneMask;
using simd::Lanes;

/// Pairs side by side in the batch's lanes.
constexpr int kPairLanes = 4;

/// Lane k of `v`.
std::array<float, kPairLanes> lane_values(Lanes v) noexcept {
  std::array<float, kPairLanes> a;
  simd::store(a.data(), v);
  return a;
}

/// The x and y lanes of four points.
struct PointLanes {
  Lanes x;
  Lanes y;
};

/// Four points (8 bytes each, anywhere) as x and y lanes: in SSE2, one 8-byte load a point and
/// four shuffles in all (`simd::lanes` takes the floats one at a time, twice the loads).
PointLanes point_lanes(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3) noexcept {
#if defined(__SSE2__)
  const auto load = [](const Vec2& p) {  // x y 0 0 (__m128i may alias anything)
    return _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&p)));
  };
  const __m128 xy01 = _mm_unpacklo_ps(load(p0), load(p1));  // x0 x1 y0 y1
  const __m128 xy23 = _mm_unpacklo_ps(load(p2), load(p3));  // x2 x3 y2 y3
  return {Lanes(_mm_movelh_ps(xy01, xy23)), Lanes(_mm_movehl_ps(xy23, xy01))};
#else
  return {simd::lanes(p0.x, p1.x, p2.x, p3.x), simd::lanes(p0.y, p1.y, p2.y, p3.y)};
#endif
}

/// Four placements as lanes: position x and y, rotation cosine and sine.
struct TransformLanes {
  PointLanes p;
  Lanes c;
  Lanes s;
};
TransformLanes transform_lanes(const Transform& x0, const Transform& x1, const Transform& x2,
                               const Transform& x3) noexcept {
#if defined(__SSE2__)
  static_assert(sizeof(Transform) == 4 * sizeof(float), "a transform is p.x, p.y, q.c, q.s");
  __m128 r0 = _mm_loadu_ps(&x0.p.x);
  __m128 r1 = _mm_loadu_ps(&x1.p.x);
  __m128 r2 = _mm_loadu_ps(&x2.p.x);
  __m128 r3 = _mm_loadu_ps(&x3.p.x);
  _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
  return {{Lanes(r0), Lanes(r1)}, Lanes(r2), Lanes(r3)};
#else
  return {point_lanes(x0.p, x1.p, x2.p, x3.p), simd::lanes(x0.q.c, x1.q.c, x2.q.c, x3.q.c),
          simd::lanes(x0.q.s, x1.q.s, x2.q.s, x3.q.s)};
#endif
}

/// contact_polygon_circle for the four pairs at `pairs`, side by side: each step of the single
/// call is made in every lane, in the same order, and each of its branches is a select (the
/// separating edge's early exit becomes a test of the greatest separation, which exceeds the
/// radii sum exactly when some edge's does), so lane k's manifold is the single call's on pair
/// k, bit for bit. The edge scan runs as many steps as the largest polygon has edges; a smaller
/// polygon repeats its last edge, whose separation is not strictly greater than itself, so its
/// edge of greatest separation is unchanged.
void contact_polygon_circle_lanes(const PolygonCirclePair* pairs, Manifold* manifolds) noexcept {
  const std::array<const Polygon*, kPairLanes> polygon{pairs[0].polygon, pairs[1].polygon,
                                                       pairs[2].polygon, pairs[3].polygon};
  const std::array<const Circle*, kPairLanes> circle{pairs[0].circle, pairs[1].circle,
                                                     pairs[2].circle, pairs[3].circle};
  const TransformLanes xa = transform_lanes(pairs[0].polygon_xf, pairs[1].polygon_xf,
                                            pairs[2].polygon_xf, pairs[3].polygon_xf);
  const TransformLanes xb = transform_lanes(pairs[0].circle_xf, pairs[1].circle_xf,
                                            pairs[2].circle_xf, pairs[3].circle_xf);
  const PointLanes centre =
      point_lanes(circle[0]->center, circle[1]->center, circle[2]->center, circle[3]->center);
  const Lanes ra =
      simd::lanes(polygon[0]->radius, polygon[1]->radius, polygon[2]->radius, polygon[3]->radius);
  const Lanes rb =
      simd::lanes(circle[0]->radius, circle[1]->radius, circle[2]->radius, circle[3]->radius);
  // B's centre in A's frame, as the single call forms it: the world offset
  // (xb.p - xa.p) + rotate(xb.q, centre), then inv_rotate(xa.q, offset).
  const Lanes wx = (xb.p.x - xa.p.x) + (xb.c * centre.x - xb.s * centre.y);
  const Lanes wy = (xb.p.y - xa.p.y) + (xb.s * centre.x + xb.c * centre.y);
  const Lanes cx = xa.c * wx + xa.s * wy;
  const Lanes cy = -xa.s * wx + xa.c * wy;
  const Lanes radius = ra + rb;

  // The edge of greatest separation, by the strict '>' of the single call's running maximum.
  std::array<const Vec2*, kPairLanes> vertices;
  std::array<const Vec2*, kPairLanes> normals;
  std::array<int, kPairLanes> count;
  std::array<int, kPairLanes> last;  // each polygon's last edge (0 for an empty one)
  int steps = 0;
  for (int k = 0; k < kPairLanes; ++k) {
    vertices[k] = polygon[k]->vertices.data();
    normals[k] = polygon[k]->normals.data();
    count[k] = polygon[k]->count;
    last[k] = std::max(count[k] - 1, 0);
    steps = std::max(steps, count[k]);
  }
  Lanes separation = simd::splat(-std::numeric_limits<float>::infinity());
  Lanes edge = simd::splat(0.0f);
  const auto scan = [&](auto same_counts) {
    for (int i = 0; i < steps; ++i) {
      // Polygons of one size (a level's tiles, all boxes) need no clamp of the index.
      const auto at = [&](int k) { return same_counts ? i : std::min(i, last[k]); };
      const int i0 = at(0), i1 = at(1), i2 = at(2), i3 = at(3);
      const PointLanes v =
          point_lanes(vertices[0][i0], vertices[1][i1], vertices[2][i2], vertices[3][i3]);
      const PointLanes n = point_lanes(normals[0][i0], normals[1][i1], normals[2][i2], normals[3][i3]);
      const Lanes s = n.x * (cx - v.x) + n.y * (cy - v.y);
      const LaneMask greater = s > separation;
      separation = simd::select(greater, s, separation);
      edge = simd::select(greater, simd::splat(static_cast<float>(i)), edge);
    }
  };
  if (count[0] == count[1] && count[2] == count[3] && count[0] == count[2]) {
    scan(std::true_type{});
  } else {
    scan(std::false_type{});
  }
  const std::array<float, kPairLanes> edge_at = lane_values(edge);
  std::array<int, kPairLanes> e;
  std::array<int, kPairLanes> next;
  for (int k = 0; k < kPairLanes; ++k) {
    e[k] = static_cast<int>(edge_at[k]);
    const int after = e[k] + 1;
    next[k] = after * static_cast<int>(after != count[k]);  // next_vertex, as arithmetic (no branch)
  }
  const PointLanes v1 =
      point_lanes(vertices[0][e[0]], vertices[1][e[1]], vertices[2][e[2]], vertices[3][e[3]]);
  const PointLanes v2 =
      point_lanes(vertices[0][next[0]], vertices[1][next[1]], vertices[2][next[2]], vertices[3][next[3]]);
  const PointLanes face =
      point_lanes(normals[0][e[0]], normals[1][e[1]], normals[2][e[2]], normals[3][e[3]]);

  // The end regions (edge_end_region), tested where the centre is beyond the edge or the
  // polygon is a segment's two sides.
  const Lanes zero = simd::splat(0.0f);
  const LaneMask two_vertex =
      simd::masks(count[0] == 2, count[1] == 2, count[2] == 2, count[3] == 2);
  const LaneMask test_ends = (separation > zero) | two_vertex;
  const LaneMask before_v1 = (cx - v1.x) * (v2.x - v1.x) + (cy - v1.y) * (v2.y - v1.y) < zero;
  const LaneMask after_v2 = (cx - v2.x) * (v1.x - v2.x) + (cy - v2.y) * (v1.y - v2.y) < zero;
  const LaneMask at_v1 = test_ends & before_v1;
  const LaneMask at_v2 = test_ends & ~before_v1 & after_v2;
  const LaneMask at_end = at_v1 | at_v2;
  const Lanes vx = simd::select(at_v1, v1.x, v2.x);
  const Lanes vy = simd::select(at_v1, v1.y, v2.y);
  const Lanes dx = cx - vx;
  const Lanes dy = cy - vy;
  const Lanes dist2 = dx * dx + dy * dy;
  const LaneMask end_too_far = at_end & ~(dist2 <= radius * radius);
  const Lanes dist = simd::sqrt(dist2);
  // (else c sits on the vertex: the face normal serves)
  const LaneMask use_end = at_end & (dist > zero);
  const Lanes inverse = simd::splat(1.0f) / dist;
  const Lanes nx = simd::select(use_end, dx * inverse, face.x);
  const Lanes ny = simd::select(use_end, dy * inverse, face.y);
  const Lanes core_x = simd::select(use_end, vx, cx - separation * face.x);
  const Lanes core_y = simd::select(use_end, vy, cy - separation * face.y);
  const Lanes distance = simd::select(use_end, dist, separation);
  const Lanes half = simd::splat(0.5f) * (ra + distance - rb);
  const Lanes mid_x = core_x + half * nx;
  const Lanes mid_y = core_y + half * ny;

  // The manifolds: a touching lane's values, an empty lane's all zero (as Manifold{}), written
  // without a branch on which lanes touch or which feature made the point (GCC turned the
  // ternaries of a first version into branches, mispredicted on unrelated pairs).
  const LaneMask touching = ~((separation > radius) | end_too_far);
  const auto keep = [&](Lanes v) { return lane_values(simd::select(touching, v, zero)); };
  const auto normal_x = keep(xa.c * nx - xa.s * ny);
  const auto normal_y = keep(xa.s * nx + xa.c * ny);
  const auto point_x = keep(xa.p.x + (xa.c * mid_x - xa.s * mid_y));
  const auto point_y = keep(xa.p.y + (xa.s * mid_x + xa.c * mid_y));
  const auto depth = keep(radius - distance);
  const unsigned touches = simd::lane_bits(touching);
  const unsigned vertex_point = simd::lane_bits(use_end);
  const unsigned first_end = simd::lane_bits(at_v1);
  static_assert(static_cast<unsigned>(FeatureType::vertex) == 0,
                "an empty manifold's id is all zero");
  for (int k = 0; k < kPairLanes; ++k) {
    const unsigned touch = (touches >> k) & 1u;
    const unsigned vertex = (vertex_point >> k) & 1u;
    const unsigned at_next = vertex & ~(first_end >> k) & 1u;  // the point is the edge's second end
    const auto feature =
        static_cast<std::uint32_t>(e[k] + static_cast<int>(at_next) * (next[k] - e[k]));
    const auto type = static_cast<unsigned>(FeatureType::edge) * (vertex ^ 1u);  // vertex is 0
    Manifold& m = manifolds[k];
    m = Manifold{};
    m.normal = {normal_x[k], normal_y[k]};
    m.points[0].point = {point_x[k], point_y[k]};
    m.points[0].depth = depth[k];
    m.points[0].id = {feature * touch, 0, static_cast<FeatureType>(type * touch),
                      static_cast<FeatureType>(static_cast<unsigned>(FeatureType::face) * touch)};
    m.count = static_cast<int>(touch);
  }
}

}  // namespace

}  // namespace collide::detail

namespace collide {

void contact(std::span<const PolygonCirclePair> pairs, std::span<Manifold> manifolds) noexcept {
  COLLIDE_ASSERT(manifolds.size() >= pairs.size(), "contact: fewer manifolds than pairs");
  const std::size_t n = std::min(pairs.size(), manifolds.size());
  constexpr std::size_t kLanes = detail::kPairLanes;
  std::size_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    detail::contact_polygon_circle_lanes(&pairs[i], &manifolds[i]);
  }
  for (; i < n; ++i) {
    const PolygonCirclePair& p = pairs[i];
    manifolds[i] = detail::contact_polygon_circle(*p.polygon, p.polygon_xf, *p.circle, p.circle_xf);
  }
}

}  // namespace collide
