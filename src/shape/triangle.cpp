#include <collide/shape/triangle.hpp>

#include "watertight_ray.hpp"

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace collide {

Triangle make_triangle(Vec3 a, Vec3 b, Vec3 c) {
  const std::array<Vec3, 3> v{a, b, c};
  for (int k = 0; k < 3; ++k) {
    if (!is_finite(v[k])) throw InvalidInput("triangle vertex " + std::to_string(k) + ": not finite");
  }
  // Twice the area against the longest edge squared, in double so that neither overflows.
  const glm::dvec3 da(a), db(b), dc(c);
  const double area2 = glm::length(glm::cross(db - da, dc - da));
  const double longest2 = std::max({glm::dot(db - da, db - da), glm::dot(dc - db, dc - db), glm::dot(da - dc, da - dc)});
  if (!(area2 > 2.0 * static_cast<double>(kDegenerateAreaTolerance) * longest2)) {
    throw InvalidInput("triangle: degenerate (repeated or collinear vertices, no area)");
  }
  return Triangle{v};
}

glm::dvec3 triangle_area_normal_at_widest_corner(Vec3 a, Vec3 b, Vec3 c) noexcept {
  const glm::dvec3 da(a), db(b), dc(c);
  const glm::dvec3 ab = db - da, bc = dc - db, ca = da - dc;
  const double lab = glm::dot(ab, ab), lbc = glm::dot(bc, bc), lca = glm::dot(ca, ca);
  // (b - a) x (c - a) = ca x ab (at a) = ab x bc (at b) = bc x ca (at c)
  if (lbc >= lab && lbc >= lca) return glm::cross(ca, ab);
  if (lca >= lab) return glm::cross(ab, bc);
  return glm::cross(bc, ca);
}

Aabb3 compute_aabb(const Triangle& triangle, const Transform3& xf) noexcept {
  const Frame3 f = Frame3::from(xf);
  const Vec3 a = transform_point(f, triangle.vertices[0]);
  const Vec3 b = transform_point(f, triangle.vertices[1]);
  const Vec3 c = transform_point(f, triangle.vertices[2]);
  return {glm::min(glm::min(a, b), c), glm::max(glm::max(a, b), c)};
}

float ray_triangle_fraction(const Ray3& ray, Vec3 a, Vec3 b, Vec3 c, float max_fraction) noexcept {
  const detail::WatertightRay r(ray);
  return r.valid ? r.fraction(a, b, c, max_fraction) : -1.0f;
}

/// closest_point_on_triangle: a triangle whose width (twice its area over its longest edge)
/// is below this fraction of its longest edge is taken by its edges alone. 2^-40: far below
/// float's resolution of the edge's length, far above double's rounding of the edge vectors.
constexpr double kNeedleWidthRatio = 0x1p-40;

// The Voronoi regions of Ericson 5.1.5 in another grouping: p projects into the face when it is
// inside all three edges' in-plane normals (the face region); every other region's nearest
// point lies on an edge or at a vertex, and the nearest of the three clamped edge points is it.
// In double: the differences of float corners are exact there, and nothing overflows for any
// float input. In float, Ericson's region tests (differences of products of dot products) and
// the normal (from two nearly parallel edges) both cancel on slivers: on a triangle 2 units
// long and 1e-8 wide the answers were off by more than a unit. Scalar double costs about what
// scalar float does.
TrianglePoint closest_point_on_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) noexcept {
  const glm::dvec3 dp(p), da(a), db(b), dc(c);
  const glm::dvec3 ab = db - da, bc = dc - db, ca = da - dc;
  const glm::dvec3 ap = dp - da, bp = dp - db, cp = dp - dc;
  const glm::dvec3 n = triangle_area_normal(a, b, c);
  const double nn = glm::dot(n, n);
  // Twice the signed areas of (p', b, c), (a, p', c), (a, b, p') times |n|, p' the projection:
  // each the point's offset along its edge's in-plane inward normal.
  const double wa = glm::dot(bp, glm::cross(n, bc)), wb = glm::dot(cp, glm::cross(n, ca)),
               wc = glm::dot(ap, glm::cross(n, ab));
  // A needle narrower than kNeedleWidthRatio of its length has no face region double can
  // tell: its edge vectors round its width away (a corner 1e-20 beside another, 4.5 from the
  // third), the three tests read 0 or noise, and a point beyond its tip was "over the face" at
  // distance 0 (the fuzzer's height field check, stop 105). Its nearest edge point is then the
  // answer, within the width of the nearest point of the face.
  const auto has_face = [&] {
    const double longest2 = std::max({glm::dot(ab, ab), glm::dot(bc, bc), glm::dot(ca, ca)});
    return nn > kNeedleWidthRatio * kNeedleWidthRatio * longest2 * longest2;
  };
  if (wa >= 0.0 && wb >= 0.0 && wc >= 0.0 && has_face()) {
    return {Vec3(dp - n * (glm::dot(ap, n) / nn)), Vec3(glm::dvec3(wa, wb, wc) / (wa + wb + wc))};
  }
  // (a zero-length edge: its parameter 0, the distance to its one point)
  auto parameter = [](const glm::dvec3& w, const glm::dvec3& e) {
    const double ee = glm::dot(e, e);
    return ee > 0.0 ? std::clamp(glm::dot(w, e) / ee, 0.0, 1.0) : 0.0;
  };
  const double t_ab = parameter(ap, ab), t_bc = parameter(bp, bc), t_ca = parameter(cp, ca);
  const glm::dvec3 on_ab = ap - t_ab * ab, on_bc = bp - t_bc * bc, on_ca = cp - t_ca * ca;  // p minus each edge point
  const double d_ab = glm::dot(on_ab, on_ab), d_bc = glm::dot(on_bc, on_bc), d_ca = glm::dot(on_ca, on_ca);
  const auto t = [](double x) { return static_cast<float>(x); };
  if (d_ab <= d_bc && d_ab <= d_ca) return {Vec3(da + t_ab * ab), {t(1.0 - t_ab), t(t_ab), 0.0f}};
  if (d_bc <= d_ca) return {Vec3(db + t_bc * bc), {0.0f, t(1.0 - t_bc), t(t_bc)}};
  return {Vec3(dc + t_ca * ca), {t(t_ca), 0.0f, t(1.0 - t_ca)}};
}

std::uint8_t active_edge_sides(Vec3 n1, Vec3 n2, Vec3 e, bool consistent, float cos_threshold) noexcept {
  const float cos_angle = dot(n1, n2);
  if (cos_angle < kFoldBackCosAngle) return 3u;
  if (!(cos_angle < cos_threshold)) return 0u;  // flat from both sides
  if (!consistent) return 3u;
  const float turn = dot(cross(n1, n2), e);
  // Convex from the front, or from behind; neither when the turn has no sign.
  return turn > 0.0f ? 1u : turn < 0.0f ? 2u : 0u;
}

}  // namespace collide
