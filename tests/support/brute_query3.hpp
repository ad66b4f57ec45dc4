#pragma once
// Slow reference answers for 3D point queries and ray casts, in double precision, built only on
// the distances of brute_convex3.hpp (minima over points, segments and triangles; no Voronoi
// regions, no slabs, no quadratics):
// - the signed distance of a point (inside a polytope core: minus the distance to its nearest
//   triangle);
// - a ray's first entry: the distance from the swept part of the ray [origin, origin + t D] to
//   the shape only decreases with t, so the smallest t where it reaches zero is found by
//   bisection; the normal there is the numerical gradient of the distance just outside.

#include "brute_convex3.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace collide::test {

/// Signed distance from world point p to the shape (core grown by its radius): negative inside.
inline double brute_signed_distance(const BruteCore& c, DVec3 p) {
  const BruteCore point{{p}, {}, 0.0};
  const double outside = brute_core_distance(point, c);
  if (outside > 0.0 || c.triangles.empty()) return outside - c.radius;
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : c.triangles) {
    best = std::min(best, point_triangle_d2(p, c.points[t[0]], c.points[t[1]], c.points[t[2]]));
  }
  return -std::sqrt(best) - c.radius;
}

/// Support function of the shape: the largest n . x over its points, for a unit n.
inline double brute_support(const BruteCore& c, DVec3 n) {
  double best = -std::numeric_limits<double>::infinity();
  for (const DVec3& p : c.points) best = std::max(best, glm::dot(n, p));
  return best + c.radius * glm::length(n);
}

/// Gap between the segment [p, q] and the shape: core distance minus radius (<= 0 touching).
inline double brute_segment_gap(const BruteCore& c, DVec3 p, DVec3 q) {
  const BruteCore seg{{p, q}, {}, 0.0};
  return brute_core_distance(seg, c) - c.radius;
}

/// The reference answer for one ray.
struct BruteRay {
  bool starts_inside = false;  ///< the origin is in the closed shape
  bool hit = false;            ///< the ray enters the shape within its length
  double fraction = 0.0;       ///< first entry
  double chord = 0.0;          ///< length of the ray inside the shape (entry to exit or end)
  double start_distance = 0.0; ///< signed distance of the origin
  double end_gap = 0.0;        ///< gap between the whole ray and the shape (<= 0 on a hit)
  /// How deep the ray goes: minus the signed distance at the middle of its stretch inside (a
  /// lower bound of its deepest point; small when it grazes a face, an edge or a corner).
  double depth = 0.0;
  DVec3 normal{0.0};           ///< unit outward normal at the entry
};

/// Smallest t in [0, 1] with gap([o, o + t d]) <= 0, given that it is <= 0 at t = 1.
inline double brute_first_touch(const BruteCore& c, DVec3 o, DVec3 d) {
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 48; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (brute_segment_gap(c, o, o + mid * d) <= 0.0) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return hi;
}

/// Unit gradient of the (positive) distance at y, by central differences of step h.
inline DVec3 brute_gradient(const BruteCore& c, DVec3 y, double h) {
  DVec3 g;
  for (int k = 0; k < 3; ++k) {
    DVec3 e(0.0);
    e[k] = h;
    g[k] = brute_signed_distance(c, y + e) - brute_signed_distance(c, y - e);
  }
  return g / glm::length(g);
}

/// First entry of the ray o + t d, t in [0, 1], into the shape. `scale` is the size of the
/// shape: the normal is the gradient 1e-7 of it in front of the entry, so that it is the
/// entered face's normal also within a hair of an edge.
inline BruteRay brute_raycast(const BruteCore& c, DVec3 o, DVec3 d, double scale) {
  BruteRay r;
  r.start_distance = brute_signed_distance(c, o);
  r.end_gap = brute_segment_gap(c, o, o + d);
  if (r.start_distance <= 0.0) {
    r.starts_inside = true;
    return r;
  }
  if (r.end_gap > 0.0) return r;
  r.hit = true;
  r.fraction = brute_first_touch(c, o, d);
  // The exit, as the first touch of the reversed ray (1 if the ray ends inside).
  const double back = brute_signed_distance(c, o + d) <= 0.0 ? 0.0 : brute_first_touch(c, o + d, -d);
  r.chord = std::max((1.0 - back) - r.fraction, 0.0) * glm::length(d);
  r.depth = -brute_signed_distance(c, o + (0.5 * (r.fraction + 1.0 - back)) * d);
  // Just outside the entry, the distance's gradient is the outward normal there.
  const DVec3 u = d / glm::length(d);
  const DVec3 y = o + r.fraction * d - 1e-7 * scale * u;
  const double gap = brute_signed_distance(c, y);
  r.normal = brute_gradient(c, y, 1e-3 * std::max(gap, 1e-14 * scale));
  return r;
}

}  // namespace collide::test
