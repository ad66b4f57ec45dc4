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

// Ericson 5.1.5: test the Voronoi regions of a, b, c, then of the three edges, and otherwise
// project onto the face. Each region test reuses the dot products of the previous ones.
TrianglePoint closest_point_on_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) noexcept {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const float d1 = glm::dot(ab, ap);
  const float d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return {a, {1.0f, 0.0f, 0.0f}};  // vertex region a

  const Vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp);
  const float d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return {b, {0.0f, 1.0f, 0.0f}};  // vertex region b

  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {  // edge region ab
    const float v = d1 / (d1 - d3);
    return {a + v * ab, {1.0f - v, v, 0.0f}};
  }

  const Vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp);
  const float d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return {c, {0.0f, 0.0f, 1.0f}};  // vertex region c

  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {  // edge region ac
    const float w = d2 / (d2 - d6);
    return {a + w * ac, {1.0f - w, 0.0f, w}};
  }

  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {  // edge region bc
    const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), {0.0f, 1.0f - w, w}};
  }

  // Face region. Ericson's weights vb / sum, vc / sum are differences of products of dot
  // products, which cancel badly on slivers; project onto the plane instead and take the weights
  // as signed sub-areas against the normal (better conditioned, same answer in exact arithmetic).
  const Vec3 n = glm::cross(ab, ac);
  const float nn = glm::dot(n, n);
  if (!(nn > 0.0f)) {
    // Degenerate (zero-area) triangle that fell through every region test: take vertex a,
    // the only answer that is always on the triangle.
    return {a, {1.0f, 0.0f, 0.0f}};
  }
  const Vec3 q = p - n * (glm::dot(ap, n) / nn);
  const float inv = 1.0f / nn;
  // q - a = v ab + w ac, so (q - a) x ac = v n and ab x (q - a) = w n.
  const float v = std::clamp(glm::dot(n, glm::cross(q - a, ac)) * inv, 0.0f, 1.0f);
  const float w = std::clamp(glm::dot(n, glm::cross(ab, q - a)) * inv, 0.0f, 1.0f - v);
  return {q, {1.0f - v - w, v, w}};
}

bool is_edge_active(Vec3 n1, Vec3 n2, Vec3 e, bool consistent, float cos_threshold) noexcept {
  const float cos_angle = dot(n1, n2);
  if (cos_angle < kFoldBackCosAngle) return true;
  if (consistent && !(dot(cross(n1, n2), e) > 0.0f)) return false;  // concave (or flat: the threshold would say no)
  return cos_angle < cos_threshold;
}

}  // namespace collide
