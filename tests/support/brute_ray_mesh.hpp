#pragma once
// The reference answer for a ray cast against a triangle mesh, by scanning every triangle in
// double precision (tests/ccd/mesh_raycast_test.cpp, bench/mesh_raycast.cpp): each triangle
// placed in the world, crossed by a plane / edge-side test, and every crossing classified as
// clearly inside a triangle or within rounding of an edge or of the ray's ends.

#include <collide/core/ray.hpp>
#include <collide/core/transform3.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace collide::test {

/// A triangle placed in the world, in double.
using WorldTriangle = std::array<glm::dvec3, 3>;

inline glm::dvec3 place(const Transform3& xf, glm::dvec3 local) {
  return glm::dvec3(xf.p) + glm::dquat(xf.q) * local;  // the float quaternion, rotating in double
}

/// Every triangle of a mesh in the world (mesh space = origin + stored vertex).
inline std::vector<WorldTriangle> world_triangles(const TriangleMesh& mesh, const Transform3& xf) {
  std::vector<WorldTriangle> out;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    WorldTriangle w;
    for (int k = 0; k < 3; ++k) w[k] = place(xf, glm::dvec3(mesh.origin) + glm::dvec3(mesh.corner(t, k)));
    out.push_back(w);
  }
  return out;
}

/// Where the segment crosses a triangle's plane, how far inside the triangle that point is
/// (distance to the nearest edge line, negative outside), and how much the fraction moves per
/// unit of distance moved off the plane (1 / |n . d|: grazing rays are ill-conditioned).
struct Crossing {
  double fraction;
  double margin;
  double fraction_per_distance;
};
inline std::optional<Crossing> crossing(glm::dvec3 o, glm::dvec3 d, const WorldTriangle& t) {
  const glm::dvec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
  const double len = glm::length(n), denom = glm::dot(n, d);
  if (len == 0.0 || denom == 0.0) return std::nullopt;
  const double f = glm::dot(n, t[0] - o) / denom;
  if (!(f >= 0.0 && f <= 1.0)) return std::nullopt;
  const glm::dvec3 q = o + f * d;
  double margin = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 e = t[(k + 1) % 3] - t[k];
    margin = std::min(margin, glm::dot(n, glm::cross(e, q - t[k])) / (len * glm::length(e)));
  }
  return Crossing{f, margin, len / std::abs(denom)};
}

/// The truth for one ray by scanning every triangle: the nearest crossing clearly inside a
/// triangle (by more than `eps`), and the nearest one that may count within rounding (inside or
/// within `eps` of an edge), each widened by its rounding (`eps` off the plane, in fraction).
/// A ray cast must return a fraction between the two, and may miss only when there is no clear
/// crossing. Crossings within rounding of the ray's ends are ambiguous too (the start excludes
/// a surface, the end includes one).
struct RayTruth {
  double clear = std::numeric_limits<double>::infinity();     ///< upper bound of the hit fraction
  double possible = std::numeric_limits<double>::infinity();  ///< lower bound
  /// The nearest crossing of a closed triangle (margin >= 0) in [0, 1], exact in double: the
  /// answer to measure a hit's error against (infinity when none).
  double nearest = std::numeric_limits<double>::infinity();
  std::size_t clear_count = 0, possible_count = 0;
};
inline RayTruth brute_ray_truth(const std::vector<WorldTriangle>& tris, const Ray3& ray, double eps,
                                double eps_fraction, const std::vector<bool>* holes = nullptr) {
  RayTruth truth;
  const glm::dvec3 o(ray.origin), d(ray.translation);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    if (holes && (*holes)[t]) continue;
    const auto c = crossing(o, d, tris[t]);
    if (!c) continue;
    if (c->margin >= 0.0) truth.nearest = std::min(truth.nearest, c->fraction);
    const double tol = eps_fraction + 2.0 * eps * c->fraction_per_distance;
    // A position error off the plane moves a grazing ray's crossing along it by more.
    const double margin_eps = eps * (1.0 + glm::length(d) * c->fraction_per_distance);
    if (c->margin < -margin_eps || c->fraction < -tol || c->fraction > 1.0 + tol) continue;
    truth.possible = std::min(truth.possible, c->fraction - tol);
    ++truth.possible_count;
    if (c->margin > margin_eps && c->fraction > tol && c->fraction < 1.0 - tol) {
      truth.clear = std::min(truth.clear, c->fraction + tol);
      ++truth.clear_count;
    }
  }
  return truth;
}

}  // namespace collide::test
