#pragma once
// Independent truths for the contact tests: Box2D 2.4 manifolds in world space, and brute-force
// geometry on world-space cores (point sets grown by a radius).

#include <box2d/box2d.h>

#include <algorithm>
#include <collide/narrow/contact.hpp>
#include <limits>
#include <vector>

#include "support/test_util.hpp"

namespace collide::contact_test {

// ---- Box2D -------------------------------------------------------------------------------

inline b2Vec2 to_b2(Vec2 v) { return {v.x, v.y}; }
inline Vec2 from_b2(b2Vec2 v) { return {v.x, v.y}; }

inline b2Transform to_b2(const Transform& xf) {
  b2Rot q;
  q.s = xf.q.s;
  q.c = xf.q.c;
  return b2Transform(to_b2(xf.p), q);
}

/// Box2D polygon with the exact geometry of ours (Box2D's default skin radius set to ours).
inline b2PolygonShape to_b2(const Polygon& p) {
  std::vector<b2Vec2> pts;
  for (int i = 0; i < p.count; ++i) pts.push_back(to_b2(p.vertices[i]));
  b2PolygonShape shape;
  shape.Set(pts.data(), static_cast<int32>(pts.size()));
  shape.m_radius = p.radius;
  return shape;
}
inline b2CircleShape to_b2(const Circle& c) {
  b2CircleShape shape;
  shape.m_p = to_b2(c.center);
  shape.m_radius = c.radius;
  return shape;
}
/// Two-sided edge of zero thickness.
inline b2EdgeShape to_b2(const Segment& s) {
  b2EdgeShape shape;
  shape.SetTwoSided(to_b2(s.a), to_b2(s.b));
  shape.m_radius = 0.0f;
  return shape;
}

struct OraclePoint {
  Vec2 point;
  float depth;
};
/// A Box2D manifold in world space, keeping only points that really touch (separation <= 0):
/// Box2D also reports speculative points up to its skin radius.
struct OracleManifold {
  Vec2 normal{0.0f, 0.0f};
  std::vector<OraclePoint> points;
};

inline OracleManifold box2d_world(const b2Manifold& m, const Transform& xa, float ra,
                                  const Transform& xb, float rb) {
  OracleManifold out;
  if (m.pointCount == 0) return out;
  b2WorldManifold wm;
  wm.Initialize(&m, to_b2(xa), ra, to_b2(xb), rb);
  out.normal = from_b2(wm.normal);
  for (int i = 0; i < m.pointCount; ++i) {
    if (wm.separations[i] <= 0.0f)
      out.points.push_back({from_b2(wm.points[i]), -wm.separations[i]});
  }
  return out;
}

/// Box2D's manifold for the pair, or an empty one for pairs Box2D 2.4 does not collide in this
/// order.
inline OracleManifold box2d_contact(const Polygon& a, const Transform& xa, const Polygon& b,
                                    const Transform& xb) {
  const b2PolygonShape sa = to_b2(a), sb = to_b2(b);
  b2Manifold m;
  b2CollidePolygons(&m, &sa, to_b2(xa), &sb, to_b2(xb));
  return box2d_world(m, xa, sa.m_radius, xb, sb.m_radius);
}
inline OracleManifold box2d_contact(const Circle& a, const Transform& xa, const Circle& b,
                                    const Transform& xb) {
  const b2CircleShape sa = to_b2(a), sb = to_b2(b);
  b2Manifold m;
  b2CollideCircles(&m, &sa, to_b2(xa), &sb, to_b2(xb));
  return box2d_world(m, xa, sa.m_radius, xb, sb.m_radius);
}
inline OracleManifold box2d_contact(const Polygon& a, const Transform& xa, const Circle& b,
                                    const Transform& xb) {
  const b2PolygonShape sa = to_b2(a);
  const b2CircleShape sb = to_b2(b);
  b2Manifold m;
  b2CollidePolygonAndCircle(&m, &sa, to_b2(xa), &sb, to_b2(xb));
  return box2d_world(m, xa, sa.m_radius, xb, sb.m_radius);
}
inline OracleManifold box2d_contact(const Segment& a, const Transform& xa, const Circle& b,
                                    const Transform& xb) {
  const b2EdgeShape sa = to_b2(a);
  const b2CircleShape sb = to_b2(b);
  b2Manifold m;
  b2CollideEdgeAndCircle(&m, &sa, to_b2(xa), &sb, to_b2(xb));
  return box2d_world(m, xa, 0.0f, xb, sb.m_radius);
}
inline OracleManifold box2d_contact(const Segment& a, const Transform& xa, const Polygon& b,
                                    const Transform& xb) {
  const b2EdgeShape sa = to_b2(a);
  const b2PolygonShape sb = to_b2(b);
  b2Manifold m;
  b2CollideEdgeAndPolygon(&m, &sa, to_b2(xa), &sb, to_b2(xb));
  return box2d_world(m, xa, 0.0f, xb, sb.m_radius);
}

// ---- brute force on world-space cores ------------------------------------------------------

/// A shape's core in world space: 1 point (circle), 2 (capsule, segment) or n (polygon,
/// counter-clockwise), grown by `radius`.
struct WorldCore {
  std::vector<Vec2> points;
  float radius = 0.0f;
};

inline WorldCore world_core(const Circle& c, const Transform& xf) {
  return {{transform_point(xf, c.center)}, c.radius};
}
inline WorldCore world_core(const Capsule& c, const Transform& xf) {
  return {{transform_point(xf, c.a), transform_point(xf, c.b)}, c.radius};
}
inline WorldCore world_core(const Segment& s, const Transform& xf) {
  return {{transform_point(xf, s.a), transform_point(xf, s.b)}, 0.0f};
}
inline WorldCore world_core(const Polygon& p, const Transform& xf) {
  WorldCore w;
  for (int i = 0; i < p.count; ++i) w.points.push_back(transform_point(xf, p.vertices[i]));
  w.radius = p.radius;
  return w;
}

inline float point_segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const float t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0f, 1.0f);
  return distance(p, a + t * ab);
}

/// Closest distance from p to the core's point set (0 inside a polygon core).
inline float point_core_distance(Vec2 p, const WorldCore& w) {
  const auto& v = w.points;
  const size_t n = v.size();
  if (n == 1) return distance(p, v[0]);
  if (n == 2) return point_segment_distance(p, v[0], v[1]);
  bool inside = true;
  float best = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = v[i], b = v[(i + 1) % n];
    if (cross(b - a, p - a) < 0.0f) inside = false;
    best = std::min(best, point_segment_distance(p, a, b));
  }
  return inside ? 0.0f : best;
}

inline bool segments_cross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const float d1 = cross(b - a, c - a), d2 = cross(b - a, d - a);
  const float d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

/// Separation of the cores along unit `n`: min over B of n.b minus max over A of n.a.
inline float core_separation_along(Vec2 n, const WorldCore& a, const WorldCore& b) {
  float max_a = -std::numeric_limits<float>::infinity();
  float min_b = std::numeric_limits<float>::infinity();
  for (Vec2 p : a.points) max_a = std::max(max_a, dot(n, p));
  for (Vec2 p : b.points) min_b = std::min(min_b, dot(n, p));
  return min_b - max_a;
}

/// Edge normals of a core (both sides for a 2-point core, none for a point).
inline std::vector<Vec2> core_axes(const WorldCore& w) {
  std::vector<Vec2> axes;
  const size_t n = w.points.size();
  if (n == 2) {
    const Vec2 e = normalize_or_zero(right_perp(w.points[1] - w.points[0]));
    axes = {e, -e};
  } else if (n >= 3) {
    for (size_t i = 0; i < n; ++i) {
      axes.push_back(normalize_or_zero(right_perp(w.points[(i + 1) % n] - w.points[i])));
    }
  }
  return axes;
}

/// Signed distance between the cores: their distance when apart; when they overlap, minus the
/// smallest translation that separates them (the largest separation over both cores' edge
/// normals, which is where the minimum translation lies for convex polygons and segments).
inline float signed_core_distance(const WorldCore& a, const WorldCore& b) {
  float dist = std::numeric_limits<float>::infinity();
  for (Vec2 p : a.points) dist = std::min(dist, point_core_distance(p, b));
  for (Vec2 p : b.points) dist = std::min(dist, point_core_distance(p, a));
  bool crossing = false;
  const size_t na = a.points.size(), nb = b.points.size();
  if (na >= 2 && nb >= 2) {
    for (size_t i = 0; i < na; ++i) {
      for (size_t j = 0; j < nb; ++j) {
        crossing = crossing || segments_cross(a.points[i], a.points[(i + 1) % na], b.points[j],
                                              b.points[(j + 1) % nb]);
      }
    }
  }
  if (dist > 0.0f && !crossing) return dist;
  float best = -std::numeric_limits<float>::infinity();
  for (Vec2 n : core_axes(a)) best = std::max(best, core_separation_along(n, a, b));
  for (Vec2 n : core_axes(b)) best = std::max(best, core_separation_along(-n, a, b));
  if (na == 1 && nb == 1) best = 0.0f;  // coincident centres
  return std::min(best, 0.0f);
}

/// Penetration depth of the rounded shapes (negative when apart).
inline float true_depth(const WorldCore& a, const WorldCore& b) {
  return a.radius + b.radius - signed_core_distance(a, b);
}

// ---- comparing manifolds -------------------------------------------------------------------

/// Every point of `m` has a point of `o` within `tol` (and the same depth within `tol`), and
/// vice versa.
inline ::testing::AssertionResult same_points(const Manifold& m, const OracleManifold& o,
                                              float tol) {
  if (m.count != static_cast<int>(o.points.size())) {
    return ::testing::AssertionFailure() << "count " << m.count << " vs oracle " << o.points.size();
  }
  for (int i = 0; i < m.count; ++i) {
    bool found = false;
    for (const OraclePoint& p : o.points) {
      found = found || (distance(m.points[i].point, p.point) <= tol &&
                        std::fabs(m.points[i].depth - p.depth) <= tol);
    }
    if (!found) {
      return ::testing::AssertionFailure()
             << "point " << i << " (" << m.points[i].point.x << ", " << m.points[i].point.y
             << ") depth " << m.points[i].depth << " has no match in the oracle";
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace collide::contact_test
