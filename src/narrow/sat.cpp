#include <collide/narrow/sat.hpp>

#include <collide/core/error.hpp>

#include <array>
#include <limits>

namespace collide {

// Separating axis test over the edge normals of polygon 1 (Ericson 5.2.1). For edge i, the
// separation of polygon 2 along the outward normal n_i is the smallest signed distance of its
// vertices to the edge's line: min_j dot(n_i, v2_j - v1_i) = min_j dot(n_i, v2_j) - dot(n_i, v1_i).
// The largest of these over i is the axis of greatest separation (> 0: apart) or, when every
// axis overlaps, of least penetration.
EdgeSeparation find_max_separation(std::span<const Vec2> vertices1,
                                   std::span<const Vec2> normals1,
                                   std::span<const Vec2> vertices2, float early_exit) noexcept {
  COLLIDE_ASSERT(vertices1.size() == normals1.size() && !vertices1.empty() && !vertices2.empty(),
                 "find_max_separation: bad polygon sizes");
  const int n1 = static_cast<int>(vertices1.size());
  const int n2 = static_cast<int>(vertices2.size());
  EdgeSeparation best{0, -std::numeric_limits<float>::infinity()};
  for (int i = 0; i < n1; ++i) {
    const Vec2 n = normals1[i];
    float lowest = dot(n, vertices2[0]);
    for (int j = 1; j < n2; ++j) {
      const float d = dot(n, vertices2[j]);
      lowest = d < lowest ? d : lowest;
    }
    const float separation = lowest - dot(n, vertices1[i]);
    if (separation > best.separation) {
      best = {i, separation};
      if (separation > early_exit) break;  // a separating axis: the shapes are apart
    }
  }
  return best;
}

EdgeSeparation find_max_separation(const Polygon& a, const Polygon& b,
                                   const Transform& b_in_a) noexcept {
  std::array<Vec2, kMaxPolygonVertices> b_vertices;
  for (int j = 0; j < b.count; ++j) b_vertices[j] = transform_point(b_in_a, b.vertices[j]);
  return find_max_separation(std::span(a.vertices.data(), a.count),
                             std::span(a.normals.data(), a.count),
                             std::span(b_vertices.data(), b.count));
}

}  // namespace collide
