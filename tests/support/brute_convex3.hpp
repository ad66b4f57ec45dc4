#pragma once
// Slow, obviously correct reference geometry for 3D tests, in double precision and written
// independently of the library's algorithms (no GJK, no Voronoi regions, no clipping): a convex
// core is a point, a segment or a triangulated closed polytope; distances are minima over
// element pairs, overlap is "an element crosses the other, or one lies inside the other".

#include <collide/core/transform3.hpp>
#include <collide/shape/box.hpp>
#include <collide/shape/capsule3.hpp>
#include <collide/shape/convex_hull.hpp>
#include <collide/shape/segment3.hpp>
#include <collide/shape/sphere.hpp>

#include <glm/vec3.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <variant>
#include <vector>

namespace collide::test {

using DVec3 = glm::dvec3;

/// A convex core in world space, double precision: 1 point, 2 (a segment), or a closed
/// polytope given by its vertices and outward-wound triangles; plus a rounding radius.
struct BruteCore {
  std::vector<DVec3> points;
  std::vector<std::array<int, 3>> triangles;  ///< empty unless a polytope
  double radius = 0.0;
};

inline DVec3 to_world(const Transform3& xf, Vec3 p) {
  const glm::dquat q(xf.q.w, xf.q.x, xf.q.y, xf.q.z);
  return DVec3(xf.p) + q * DVec3(p);
}

inline BruteCore brute_core(const Sphere& s, const Transform3& xf) {
  return {{to_world(xf, s.center)}, {}, s.radius};
}
inline BruteCore brute_core(const Capsule3& c, const Transform3& xf) {
  return {{to_world(xf, c.a), to_world(xf, c.b)}, {}, c.radius};
}
inline BruteCore brute_core(const Segment3& s, const Transform3& xf) {
  return {{to_world(xf, s.a), to_world(xf, s.b)}, {}, 0.0};
}
inline BruteCore brute_core(const Box& b, const Transform3& xf) {
  BruteCore c;
  for (int i = 0; i < 8; ++i) c.points.push_back(to_world(xf, b.vertex(i)));
  // Faces as two triangles each, wound outward (corner bit k = + side on axis k).
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    c.triangles.push_back({q[0], q[1], q[2]});
    c.triangles.push_back({q[0], q[2], q[3]});
  }
  c.radius = b.radius;
  return c;
}

inline BruteCore brute_core(const ConvexHull& h, const Transform3& xf) {
  BruteCore c;
  for (const Vec3& v : h.vertices) c.points.push_back(to_world(xf, v));
  // Each polygonal face as a fan of triangles (wound as the face: outward).
  for (const HullFace& f : h.faces) {
    for (int k = 1; k + 1 < f.count; ++k) {
      c.triangles.push_back({h.face_vertices[f.first], h.face_vertices[f.first + k],
                             h.face_vertices[f.first + k + 1]});
    }
  }
  c.radius = h.radius;
  return c;
}

/// The core of any convex 3D shape.
template <class Variant>
inline BruteCore brute_core_of(const Variant& s, const Transform3& xf) {
  return std::visit([&](const auto& v) { return brute_core(v, xf); }, s);
}

inline DVec3 closest_on_segment(DVec3 a, DVec3 b, DVec3 p) {
  const DVec3 e = b - a;
  const double ee = glm::dot(e, e);
  const double s = ee > 0.0 ? std::clamp(glm::dot(p - a, e) / ee, 0.0, 1.0) : 0.0;
  return a + s * e;
}

/// Squared distance between segments p0-p1 and q0-q1 (Ericson, Real-Time Collision Detection,
/// 5.1.9, in double), checked against the four end-to-segment distances.
inline double segment_segment_d2(DVec3 p0, DVec3 p1, DVec3 q0, DVec3 q1) {
  const DVec3 d1 = p1 - p0;
  const DVec3 d2 = q1 - q0;
  const DVec3 r = p0 - q0;
  const double a = glm::dot(d1, d1);
  const double e = glm::dot(d2, d2);
  const double f = glm::dot(d2, r);
  double best = std::numeric_limits<double>::infinity();
  const auto consider = [&](DVec3 x, DVec3 y) { best = std::min(best, glm::dot(x - y, x - y)); };
  consider(p0, closest_on_segment(q0, q1, p0));
  consider(p1, closest_on_segment(q0, q1, p1));
  consider(q0, closest_on_segment(p0, p1, q0));
  consider(q1, closest_on_segment(p0, p1, q1));
  if (a > 0.0 && e > 0.0) {
    const double b = glm::dot(d1, d2);
    const double c = glm::dot(d1, r);
    const double denom = a * e - b * b;
    if (denom > 1e-12 * a * e) {
      const double s = (b * f - c * e) / denom;
      const double t = (a * f - b * c) / denom;
      if (s >= 0.0 && s <= 1.0 && t >= 0.0 && t <= 1.0) consider(p0 + s * d1, q0 + t * d2);
    }
  }
  return best;
}

/// Squared distance from p to the closed triangle (a, b, c): the projection if it falls inside,
/// else the nearest edge.
inline double point_triangle_d2(DVec3 p, DVec3 a, DVec3 b, DVec3 c) {
  const DVec3 n = glm::cross(b - a, c - a);
  const double nn = glm::dot(n, n);
  double best = std::numeric_limits<double>::infinity();
  if (nn > 0.0) {
    const DVec3 q = p - (glm::dot(p - a, n) / nn) * n;
    const double u = glm::dot(glm::cross(c - b, q - b), n);
    const double v = glm::dot(glm::cross(a - c, q - c), n);
    const double w = glm::dot(glm::cross(b - a, q - a), n);
    if (u >= 0.0 && v >= 0.0 && w >= 0.0) best = glm::dot(p - q, p - q);
  }
  for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
    const DVec3 q = closest_on_segment(x, y, p);
    best = std::min(best, glm::dot(p - q, p - q));
  }
  return best;
}

/// True when segment p0-p1 crosses the closed triangle (a, b, c).
inline bool segment_crosses_triangle(DVec3 p0, DVec3 p1, DVec3 a, DVec3 b, DVec3 c) {
  const DVec3 n = glm::cross(b - a, c - a);
  const double d0 = glm::dot(p0 - a, n);
  const double d1 = glm::dot(p1 - a, n);
  if ((d0 > 0.0 && d1 > 0.0) || (d0 < 0.0 && d1 < 0.0)) return false;
  if (d0 == d1) return false;  // in the plane: the edge distances decide
  const DVec3 q = p0 + (d0 / (d0 - d1)) * (p1 - p0);
  const double u = glm::dot(glm::cross(c - b, q - b), n);
  const double v = glm::dot(glm::cross(a - c, q - c), n);
  const double w = glm::dot(glm::cross(b - a, q - a), n);
  return u >= 0.0 && v >= 0.0 && w >= 0.0;
}

/// True when p lies in the closed polytope (behind every outward triangle's plane).
inline bool inside_polytope(const BruteCore& c, DVec3 p) {
  for (const auto& t : c.triangles) {
    const DVec3 a = c.points[t[0]];
    const DVec3 n = glm::cross(c.points[t[1]] - a, c.points[t[2]] - a);
    if (glm::dot(p - a, n) > 1e-12 * glm::length(n) * (1.0 + glm::length(p - a))) return false;
  }
  return true;
}

/// The core's elements: its points' segments, or its triangles' edges.
inline std::vector<std::array<DVec3, 2>> brute_edges(const BruteCore& c) {
  std::vector<std::array<DVec3, 2>> out;
  if (c.triangles.empty()) {
    out.push_back({c.points.front(), c.points.back()});
  } else {
    for (const auto& t : c.triangles) {
      for (int k = 0; k < 3; ++k) out.push_back({c.points[t[k]], c.points[t[(k + 1) % 3]]});
    }
  }
  return out;
}

/// Distance between the two cores (radii not applied): 0 when they overlap.
inline double brute_core_distance(const BruteCore& x, const BruteCore& y) {
  const bool px = !x.triangles.empty();
  const bool py = !y.triangles.empty();
  // Containment or crossing: overlapping.
  if (py) {
    for (const DVec3& p : x.points) {
      if (inside_polytope(y, p)) return 0.0;
    }
    for (const auto& e : brute_edges(x)) {
      for (const auto& t : y.triangles) {
        if (segment_crosses_triangle(e[0], e[1], y.points[t[0]], y.points[t[1]], y.points[t[2]])) {
          return 0.0;
        }
      }
    }
  }
  if (px) {
    for (const DVec3& p : y.points) {
      if (inside_polytope(x, p)) return 0.0;
    }
    for (const auto& e : brute_edges(y)) {
      for (const auto& t : x.triangles) {
        if (segment_crosses_triangle(e[0], e[1], x.points[t[0]], x.points[t[1]], x.points[t[2]])) {
          return 0.0;
        }
      }
    }
  }
  double best = std::numeric_limits<double>::infinity();
  for (const auto& e : brute_edges(x)) {
    for (const auto& f : brute_edges(y)) best = std::min(best, segment_segment_d2(e[0], e[1], f[0], f[1]));
  }
  if (py) {
    for (const DVec3& p : x.points) {
      for (const auto& t : y.triangles) {
        best = std::min(best, point_triangle_d2(p, y.points[t[0]], y.points[t[1]], y.points[t[2]]));
      }
    }
  }
  if (px) {
    for (const DVec3& p : y.points) {
      for (const auto& t : x.triangles) {
        best = std::min(best, point_triangle_d2(p, x.points[t[0]], x.points[t[1]], x.points[t[2]]));
      }
    }
  }
  return std::sqrt(best);
}

/// Distance between the shapes (radii applied, 0 when overlapping), and the signed gap
/// (negative: the rounded shapes overlap by that much, only meaningful when the cores are apart).
inline double brute_distance(const BruteCore& x, const BruteCore& y) {
  return std::max(brute_core_distance(x, y) - x.radius - y.radius, 0.0);
}

/// Distance from world point p to the solid core grown by its radius (0 inside).
inline double brute_point_distance(const BruteCore& c, DVec3 p) {
  const BruteCore point{{p}, {}, 0.0};
  return std::max(brute_core_distance(point, c) - c.radius, 0.0);
}

/// First time t in [0, 1] at which a distance that is convex in t (two translating convex
/// shapes) reaches 0, or -1 when it never does; `min_distance` gets its least value over the
/// step. A ternary search for the closest approach, then a bisection before it.
template <class DistanceAt>
double brute_first_touch(const DistanceAt& distance_at, double& min_distance) {
  double lo = 0.0;
  double hi = 1.0;
  for (int i = 0; i < 40; ++i) {
    const double m1 = lo + (hi - lo) / 3.0;
    const double m2 = hi - (hi - lo) / 3.0;
    if (distance_at(m1) <= distance_at(m2)) hi = m2; else lo = m1;
  }
  const double t_min = 0.5 * (lo + hi);
  min_distance = std::min({distance_at(t_min), distance_at(0.0), distance_at(1.0)});
  if (min_distance > 0.0) return -1.0;
  if (distance_at(0.0) <= 0.0) return 0.0;
  double a = 0.0;
  double b = distance_at(t_min) <= 0.0 ? t_min : 1.0;
  for (int i = 0; i < 40; ++i) {
    const double m = 0.5 * (a + b);
    if (distance_at(m) > 0.0) a = m; else b = m;
  }
  return b;
}

}  // namespace collide::test
