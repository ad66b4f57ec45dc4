#pragma once
// Independent answers for triangle queries, in double precision, by methods other than the
// library's: the closest point of a triangle (plane projection, else the best segment point)
// and the ray-triangle crossing (plane intersection, then the point's side of each edge).

#include <collide/core/math.hpp>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace collide::test {

/// Closest point of a triangle in double precision by a different method than the library's
/// Voronoi-region walk: project onto the plane; inside -> done; else the best of the three
/// segment projections.
inline glm::dvec3 brute_closest_on_triangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double nn = glm::dot(n, n);
  if (nn > 0.0) {
    const glm::dvec3 q = p - n * (glm::dot(p - a, n) / nn);
    const double wa = glm::dot(n, glm::cross(c - b, q - b));
    const double wb = glm::dot(n, glm::cross(a - c, q - c));
    const double wc = glm::dot(n, glm::cross(b - a, q - a));
    if (wa >= 0.0 && wb >= 0.0 && wc >= 0.0) return q;
  }
  auto seg = [&](glm::dvec3 s0, glm::dvec3 s1) {
    const glm::dvec3 d = s1 - s0;
    const double dd = glm::dot(d, d);
    const double t = dd > 0.0 ? std::clamp(glm::dot(p - s0, d) / dd, 0.0, 1.0) : 0.0;
    return s0 + t * d;
  };
  glm::dvec3 best = seg(a, b);
  for (const glm::dvec3 q : {seg(b, c), seg(c, a)}) {
    if (glm::length(q - p) < glm::length(best - p)) best = q;
  }
  return best;
}

/// Fraction t in [0, 1] at which the segment origin + t * translation crosses the closed
/// triangle (a, b, c), either side, in double: the plane's parameter, then the crossing point
/// must lie on the inner side of (or on) all three edges. Empty on a miss, for a degenerate
/// triangle, and for a segment parallel to the plane.
inline std::optional<double> brute_ray_triangle(glm::dvec3 origin, glm::dvec3 translation, glm::dvec3 a,
                                                glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double denom = glm::dot(n, translation);
  if (glm::dot(n, n) == 0.0 || denom == 0.0) return std::nullopt;
  const double t = glm::dot(n, a - origin) / denom;
  if (!(t >= 0.0 && t <= 1.0)) return std::nullopt;
  const glm::dvec3 q = origin + t * translation;
  const double wa = glm::dot(n, glm::cross(c - b, q - b));
  const double wb = glm::dot(n, glm::cross(a - c, q - c));
  const double wc = glm::dot(n, glm::cross(b - a, q - a));
  if (wa < 0.0 || wb < 0.0 || wc < 0.0) return std::nullopt;
  return t;
}

}  // namespace collide::test
