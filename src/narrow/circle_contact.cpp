// Contacts with a circle: circle-circle analytically, polygon-circle by the Voronoi region of
// the circle's centre. Both give one point midway between the surfaces.

#include <cmath>
#include <limits>

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

}  // namespace collide::detail
