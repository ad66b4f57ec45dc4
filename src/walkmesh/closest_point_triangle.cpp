#include <collide/walkmesh/closest_point_triangle.hpp>

namespace collide {

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

  const float sum = va + vb + vc;
  if (!(sum > 0.0f)) {
    // Degenerate (zero-area) triangle that fell through every region test: take vertex a,
    // the only answer that is always on the triangle.
    return {a, {1.0f, 0.0f, 0.0f}};
  }
  const float denom = 1.0f / sum;  // face region
  const float v = vb * denom;
  const float w = vc * denom;
  return {a + ab * v + ac * w, {1.0f - v - w, v, w}};
}

}  // namespace collide
