#include <collide/narrow/distance.hpp>

#include "gjk.hpp"

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <variant>

namespace collide {
namespace {

/// The starting simplex: the cached one if its indices are valid for these proxies and it is
/// not degenerate now (the shapes may have moved since), else the seed vertex (gjk.hpp), which
/// costs one support evaluation: `seeded` is then true.
detail::GjkSimplex start_simplex(const ConvexProxy& a, const ConvexProxy& b,
                                 const Transform& b_in_a, const SimplexCache* cache,
                                 bool& seeded) noexcept {
  detail::GjkSimplex s;
  const int cached = cache != nullptr ? cache->count : 0;
  bool valid = cached >= 1 && cached <= 3;
  for (int i = 0; i < cached && valid; ++i) {
    valid = cache->index_a[i] < a.count() && cache->index_b[i] < b.count();
  }
  if (valid) {
    for (int i = 0; i < cached; ++i) {
      s.v[i] = detail::make_vertex(a, b, b_in_a, cache->index_a[i], cache->index_b[i]);
    }
    s.count = cached;
    // Degenerate now (or repeated vertices)? An edge shorter, or a triangle thinner, than
    // rounding at this scale would give meaningless barycentric weights: keep its first vertex.
    const float tol = kRelativeTolerance * detail::gjk_scale(s.v[0], 0.0f);
    const float tol2 = tol * tol;
    if (cached >= 2) {
      const Vec2 e12 = s.v[1].w - s.v[0].w;
      const float e12_2 = dot(e12, e12);
      if (cached == 2) {
        if (!(e12_2 > tol2)) s.count = 1;
      } else {
        const Vec2 e13 = s.v[2].w - s.v[0].w;
        const float twice_area = cross(e12, e13);
        // Height over the longer edge <= tol, squared: area^2 <= tol^2 |e|^2.
        if (!(twice_area * twice_area > tol2 * std::max(e12_2, dot(e13, e13)))) s.count = 1;
      }
    }
    seeded = false;
    return s;
  }
  s.v[0] = detail::seed_vertex(a, b, b_in_a);
  s.count = 1;
  seeded = true;
  return s;
}

}  // namespace

DistanceResult gjk_distance(const ConvexProxy& a, const Transform& xa, const ConvexProxy& b,
                            const Transform& xb, SimplexCache* cache) noexcept {
  COLLIDE_ASSERT(a.count() >= 1 && a.count() <= kMaxPolygonVertices, "proxy A point count");
  COLLIDE_ASSERT(b.count() >= 1 && b.count() <= kMaxPolygonVertices, "proxy B point count");
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "distance: transforms must be finite rigid");
  const Transform b_in_a = inv_mul(xa, xb);
  const float ra = a.radius();
  const float rb = b.radius();

  bool seeded = false;
  detail::GjkSimplex s = start_simplex(a, b, b_in_a, cache, seeded);
  const float scale = detail::gjk_scale(s.v[0], ra + rb);
  DistanceResult out;
  const detail::GjkEnd end =
      detail::run_gjk(a, b, b_in_a, s, scale, detail::GjkRunToEnd{}, out.iterations);
  if (seeded) ++out.iterations;  // the seed's support evaluation counts as an iteration

  if (cache != nullptr) {
    cache->count = s.count;
    for (int i = 0; i < s.count; ++i) {
      cache->index_a[i] = static_cast<std::uint8_t>(s.v[i].ia);
      cache->index_b[i] = static_cast<std::uint8_t>(s.v[i].ib);
    }
  }

  Vec2 pa;
  Vec2 pb;
  detail::witness_points(s, pa, pb);
  const Vec2 delta = pb - pa;
  const float core_distance = length(delta);
  if (end == detail::GjkEnd::overlapped || !(core_distance > 0.0f)) {
    // Cores overlap (or touch within rounding, pa ~ pb): one point inside both, no normal.
    out.point_a = transform_point(xa, 0.5f * (pa + pb));
    out.point_b = out.point_a;
    out.status = GjkStatus::overlapped;
    return out;
  }
  out.status = end == detail::GjkEnd::max_iterations ? GjkStatus::max_iterations
                                                     : GjkStatus::separated;
  // Cores apart: move each witness out along the normal by its radius. If the radii overlap
  // (core distance < ra + rb) the moved points pass each other, dot(pb - pa, n) being minus the
  // penetration depth, and the distance clamps to 0.
  const Vec2 n = delta * (1.0f / core_distance);
  pa += ra * n;
  pb -= rb * n;
  out.distance = std::max(core_distance - (ra + rb), 0.0f);
  out.point_a = transform_point(xa, pa);
  out.point_b = transform_point(xa, pb);
  out.normal = rotate(xa.q, n);
  return out;
}

DistanceResult distance(const Shape2D& a, const Transform& xa, const Shape2D& b,
                        const Transform& xb, SimplexCache* cache) noexcept {
  return std::visit(
      [&](const auto& sa, const auto& sb) { return distance(sa, xa, sb, xb, cache); }, a, b);
}

}  // namespace collide
