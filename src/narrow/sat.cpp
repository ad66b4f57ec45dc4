#include <algorithm>
#include <array>
#include <collide/core/error.hpp>
#include <collide/narrow/sat.hpp>
#include <limits>

#include "sat_lanes.hpp"
#include "sat_soa.hpp"

namespace collide {

namespace detail {

// Separating axis test over the edge normals of polygon 1 (Ericson 5.2.1). For edge i, the
// separation of polygon 2 along the outward normal n_i is the smallest signed distance of its
// vertices to the edge's line: min_j dot(n_i, v2_j - v1_i) = min_j dot(n_i, v2_j) - dot(n_i, v1_i).
// The largest of these over i is the axis of greatest separation (> 0: apart) or, when every
// axis overlaps, of least penetration. O(n m).
//
// Scalar meaning of one step, for the four edges i..i+3 at once:
//   lowest[k] = min_j (nx[i+k] * x2[j] + ny[i+k] * y2[j])
//   separation[k] = lowest[k] - (nx[i+k] * x1[i+k] + ny[i+k] * y1[i+k])
// With GCC or Clang the four lanes are one SIMD register (generic vector extension: SSE on x86,
// NEON on ARM); elsewhere a plain loop over the lanes. A separating axis ends the test after
// its group of four.
#if defined(__GNUC__) || defined(__clang__)
namespace {
using Lanes = float __attribute__((vector_size(16)));
Lanes load(const float* p) noexcept {
  Lanes v;
  __builtin_memcpy(&v, p, sizeof(Lanes));
  return v;
}
}  // namespace
#endif

EdgeSeparation find_max_separation_soa(const SoaPolygon& p1, const SoaPolygon& p2,
                                       float early_exit) noexcept {
  EdgeSeparation best{0, -std::numeric_limits<float>::infinity(), 0};
  for (int i = 0; i < p1.padded; i += kSatLanes) {
    float separation[kSatLanes];
#if defined(__GNUC__) || defined(__clang__)
    const Lanes nx = load(p1.nx + i);
    const Lanes ny = load(p1.ny + i);
    Lanes lowest = nx * p2.x[0] + ny * p2.y[0];
    for (int j = 1; j < p2.count; ++j) {
      const Lanes d = nx * p2.x[j] + ny * p2.y[j];
      lowest = d < lowest ? d : lowest;
    }
    const Lanes s = lowest - (nx * load(p1.x + i) + ny * load(p1.y + i));
    __builtin_memcpy(separation, &s, sizeof(Lanes));
#else
    for (int k = 0; k < kSatLanes; ++k) {
      const Vec2 n = p1.normal(i + k);
      float lowest = dot(n, p2.vertex(0));
      for (int j = 1; j < p2.count; ++j) {
        const float d = dot(n, p2.vertex(j));
        lowest = d < lowest ? d : lowest;
      }
      separation[k] = lowest - dot(n, p1.vertex(i + k));
    }
#endif
    // Padded lanes repeat the last edge, so they tie with it and never win (strictly greater
    // wins). Selects rather than branches: which edge wins is data, not a pattern.
    for (int k = 0; k < kSatLanes; ++k) {
      const bool better = separation[k] > best.separation;
      best.edge = better ? i + k : best.edge;
      best.separation = better ? separation[k] : best.separation;
    }
    if (best.separation > early_exit) break;  // a separating axis: the shapes are apart
  }
  return best;
}

int deepest_vertex(const SoaPolygon& p, Vec2 n) noexcept {
  int best = 0;
  float deepest = dot(n, p.vertex(0));
  for (int j = 1; j < p.count; ++j) {
    const float d = dot(n, p.vertex(j));
    if (d < deepest) {
      deepest = d;
      best = j;
    }
  }
  return best;
}

}  // namespace detail

void edge_separations(const Polygon& a, const Polygon& b, const Transform& b_in_a,
                      std::span<float> out) noexcept {
  COLLIDE_ASSERT(out.size() >= static_cast<std::size_t>(a.count), "edge_separations: out too small");
  const Vec2 origin = a.vertices[0];
  const detail::SharedFrame f{b_in_a, origin, b_in_a.p - origin};
#if COLLIDE_SMALL_POLYGON_SSE2
  const bool small = detail::with_lane_groups(a.count, b.count, [&](auto groups_a, auto groups_b) {
    detail::LanePair<groups_a(), groups_b()> p;
    detail::load_pair(a, b, f, p);
    __m128 s[groups_a()];
    detail::separation_lanes(p.an, p.av, p.bv, s);
    alignas(16) float lanes[groups_a() * detail::kSatLanes];
    for (int g = 0; g < groups_a(); ++g) _mm_store_ps(lanes + detail::kSatLanes * g, s[g]);
    std::copy_n(lanes, a.count, out.begin());
  });
  if (small) return;
#endif
  std::array<Vec2, kMaxPolygonVertices> placed;  // B's vertices in the shifted frame
  for (int j = 0; j < b.count; ++j) placed[j] = rotate(b_in_a.q, b.vertices[j]) + f.shift;
  for (int i = 0; i < a.count; ++i) {
    const Vec2 n = a.normals[i];
    float lowest = dot(n, placed[0]);
    for (int j = 1; j < b.count; ++j) lowest = std::min(lowest, dot(n, placed[j]));
    out[i] = lowest - dot(n, a.vertices[i] - origin);
  }
}

EdgeSeparation find_max_separation(std::span<const Vec2> vertices1, std::span<const Vec2> normals1,
                                   std::span<const Vec2> vertices2, float early_exit) noexcept {
  COLLIDE_ASSERT(vertices1.size() == normals1.size() && !vertices1.empty() && !vertices2.empty() &&
                     vertices1.size() <= static_cast<size_t>(kMaxPolygonVertices) &&
                     vertices2.size() <= static_cast<size_t>(kMaxPolygonVertices),
                 "find_max_separation: bad polygon sizes");
  detail::SoaPolygon p1;
  detail::SoaPolygon p2;
  const int n1 = static_cast<int>(vertices1.size());
  const int n2 = static_cast<int>(vertices2.size());
  for (int i = 0; i < n1; ++i) {
    p1.set_vertex(i, vertices1[i]);
    p1.set_normal(i, normals1[i]);
  }
  p1.finish_vertices(n1);
  p1.finish_normals();
  for (int j = 0; j < n2; ++j) p2.set_vertex(j, vertices2[j]);
  p2.finish_vertices(n2);
  EdgeSeparation s = detail::find_max_separation_soa(p1, p2, early_exit);
  s.support = detail::deepest_vertex(p2, normals1[s.edge]);
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
