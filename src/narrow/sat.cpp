#include <collide/narrow/sat.hpp>

#include "sat_soa.hpp"

#include <collide/core/error.hpp>

#include <array>
#include <limits>

namespace collide {

namespace detail {
namespace {

// The smallest of dot(n, v2_j) over polygon 2's vertices. Scalar meaning:
//   lowest = min_j (n.x * x[j] + n.y * y[j])
// With GCC or Clang, four vertices per step in one SIMD register (generic vector extension,
// SSE on x86, NEON on ARM); elsewhere the plain loop.
#if defined(__GNUC__) || defined(__clang__)
using Lanes = float __attribute__((vector_size(16)));

float lowest_projection(const SoaVertices& v, Vec2 n) noexcept {
  Lanes x, y;
  __builtin_memcpy(&x, v.x, sizeof(Lanes));
  __builtin_memcpy(&y, v.y, sizeof(Lanes));
  Lanes lo = n.x * x + n.y * y;
  for (int j = kSatLanes; j < v.padded; j += kSatLanes) {
    __builtin_memcpy(&x, v.x + j, sizeof(Lanes));
    __builtin_memcpy(&y, v.y + j, sizeof(Lanes));
    const Lanes d = n.x * x + n.y * y;
    lo = d < lo ? d : lo;
  }
  const float a = lo[0] < lo[1] ? lo[0] : lo[1];
  const float b = lo[2] < lo[3] ? lo[2] : lo[3];
  return a < b ? a : b;
}
#else
float lowest_projection(const SoaVertices& v, Vec2 n) noexcept {
  float lo = n.x * v.x[0] + n.y * v.y[0];
  for (int j = 1; j < v.count; ++j) {
    const float d = n.x * v.x[j] + n.y * v.y[j];
    lo = d < lo ? d : lo;
  }
  return lo;
}
#endif

}  // namespace

// Separating axis test over the edge normals of polygon 1 (Ericson 5.2.1). For edge i, the
// separation of polygon 2 along the outward normal n_i is the smallest signed distance of its
// vertices to the edge's line: min_j dot(n_i, v2_j - v1_i) = min_j dot(n_i, v2_j) - dot(n_i, v1_i).
// The largest of these over i is the axis of greatest separation (> 0: apart) or, when every
// axis overlaps, of least penetration. O(n m), the m side four at a time.
EdgeSeparation find_max_separation_soa(const SoaVertices& v1, const Vec2* normals1,
                                       const SoaVertices& v2, float early_exit) noexcept {
  EdgeSeparation best{0, -std::numeric_limits<float>::infinity(), 0};
  for (int i = 0; i < v1.count; ++i) {
    const Vec2 n = normals1[i];
    const float separation = lowest_projection(v2, n) - (n.x * v1.x[i] + n.y * v1.y[i]);
    if (separation > best.separation) {
      best.edge = i;
      best.separation = separation;
      if (separation > early_exit) break;  // a separating axis: the shapes are apart
    }
  }
  return best;
}

int deepest_vertex(const SoaVertices& v, Vec2 n) noexcept {
  int best = 0;
  float deepest = dot(n, v.vertex(0));
  for (int j = 1; j < v.count; ++j) {
    const float d = dot(n, v.vertex(j));
    if (d < deepest) {
      deepest = d;
      best = j;
    }
  }
  return best;
}

}  // namespace detail

EdgeSeparation find_max_separation(std::span<const Vec2> vertices1,
                                   std::span<const Vec2> normals1,
                                   std::span<const Vec2> vertices2, float early_exit) noexcept {
  COLLIDE_ASSERT(vertices1.size() == normals1.size() && !vertices1.empty() && !vertices2.empty() &&
                     vertices1.size() <= static_cast<size_t>(kMaxPolygonVertices) &&
                     vertices2.size() <= static_cast<size_t>(kMaxPolygonVertices),
                 "find_max_separation: bad polygon sizes");
  detail::SoaVertices v1;
  detail::SoaVertices v2;
  const int n1 = static_cast<int>(vertices1.size());
  const int n2 = static_cast<int>(vertices2.size());
  for (int i = 0; i < n1; ++i) v1.set(i, vertices1[i]);
  v1.finish(n1);
  for (int j = 0; j < n2; ++j) v2.set(j, vertices2[j]);
  v2.finish(n2);
  EdgeSeparation s = detail::find_max_separation_soa(v1, normals1.data(), v2, early_exit);
  s.support = detail::deepest_vertex(v2, normals1[s.edge]);
  return s;
}

EdgeSeparation find_max_separation(const Polygon& a, const Polygon& b,
                                   const Transform& b_in_a) noexcept {
  std::array<Vec2, kMaxPolygonVertices> vb;
  for (int j = 0; j < b.count; ++j) vb[j] = transform_point(b_in_a, b.vertices[j]);
  return find_max_separation(std::span(a.vertices.data(), a.count),
                             std::span(a.normals.data(), a.count), std::span(vb.data(), b.count));
}

}  // namespace collide
