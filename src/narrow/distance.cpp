#include <collide/narrow/distance.hpp>

#include <collide/narrow/gjk.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <variant>

namespace collide {
namespace {

/// Twice the squared area of a 2D triangle edge pair / the squared area of a 3D one (both
/// |e12 x e13|^2 up to a constant factor of the 3D definition).
[[nodiscard]] inline float twice_area_squared(Vec2 e12, Vec2 e13) noexcept {
  const float a = cross(e12, e13);
  return a * a;
}
[[nodiscard]] inline float twice_area_squared(Vec3 e12, Vec3 e13) noexcept {
  return length_squared(cross(e12, e13));
}

/// The starting simplex: the cached one if its indices are valid for these proxies and it is
/// not degenerate now (the shapes may have moved since), else the seed vertex (gjk.hpp), which
/// costs one support evaluation: `seeded` is then true.
template <int D>
COLLIDE_ALWAYS_INLINE GjkSimplexN<D> start_simplex(const ConvexProxyN<D>& a, const ConvexProxyN<D>& b,
                             const FrameN<D>& b_in_a, const SimplexCacheN<D>* cache,
                             bool& seeded) noexcept {
  GjkSimplexN<D> s;
  const int cached = cache != nullptr ? cache->count : 0;
  bool valid = cached >= 1 && cached <= D + 1;
  for (int i = 0; i < cached && valid; ++i) {
    valid = cache->index_a[i] < a.count() && cache->index_b[i] < b.count();
  }
  if (valid) {
    for (int i = 0; i < cached; ++i) {
      s.v[i] = gjk_vertex<D>(a, b, b_in_a, cache->index_a[i], cache->index_b[i]);
    }
    s.count = cached;
    // Degenerate now (or repeated vertices)? An edge shorter, or a triangle thinner, than
    // rounding at this scale would give meaningless barycentric weights: keep its first vertex.
    // (A cached tetrahedron is kept as its first triangle: the loop re-grows it if needed.)
    const float tol = kRelativeTolerance * gjk_scale<D>(s.v[0], 0.0f);
    const float tol2 = tol * tol;
    if (cached >= 2) {
      const VecN<D> e12 = s.v[1].w - s.v[0].w;
      const float e12_2 = dot(e12, e12);
      if (cached == 2) {
        if (!(e12_2 > tol2)) s.count = 1;
      } else {
        const VecN<D> e13 = s.v[2].w - s.v[0].w;
        // Height over the longer edge <= tol, squared: area^2 <= tol^2 |e|^2.
        if (!(twice_area_squared(e12, e13) > tol2 * std::max(e12_2, dot(e13, e13)))) {
          s.count = 1;
        } else if (cached == 4) {
          s.count = 3;
        }
      }
    }
    seeded = false;
    return s;
  }
  s.v[0] = gjk_seed_vertex<D>(a, b, b_in_a);
  s.count = 1;
  seeded = true;
  return s;
}

}  // namespace

template <int D>
DistanceResultN<D> gjk_distance(const ConvexProxyN<D>& a, const TransformN<D>& xa,
                                const ConvexProxyN<D>& b, const TransformN<D>& xb,
                                SimplexCacheN<D>* cache) noexcept {
  COLLIDE_ASSERT(a.count() >= 1 && b.count() >= 1, "distance: proxies must hold points");
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "distance: transforms must be finite rigid");
  const FrameN<D> b_in_a = to_frame(inv_mul(xa, xb));
  const float ra = a.radius();
  const float rb = b.radius();

  bool seeded = false;
  GjkSimplexN<D> s = start_simplex<D>(a, b, b_in_a, cache, seeded);
  const float scale = gjk_scale<D>(s.v[0], ra + rb);
  DistanceResultN<D> out;
  const GjkEnd end = run_gjk<D>(a, b, b_in_a, s, scale, GjkRunToEnd{}, out.iterations);
  if (seeded) ++out.iterations;  // the seed's support evaluation counts as an iteration

  if (cache != nullptr) {
    cache->count = s.count;
    for (int i = 0; i < s.count; ++i) {
      cache->index_a[i] = static_cast<std::uint8_t>(s.v[i].ia);
      cache->index_b[i] = static_cast<std::uint8_t>(s.v[i].ib);
    }
  }

  VecN<D> pa;
  VecN<D> pb;
  gjk_witness_points(s, pa, pb);
  const VecN<D> delta = pb - pa;
  const float core_distance = length(delta);
  if (end == GjkEnd::overlapped || !(core_distance > 0.0f)) {
    // Cores overlap (or touch within rounding, pa ~ pb): one point inside both, no normal.
    out.point_a = transform_point(xa, 0.5f * (pa + pb));
    out.point_b = out.point_a;
    out.status = QueryStatus::overlapped;
    return out;
  }
  out.status = end == GjkEnd::max_iterations ? QueryStatus::max_iterations
                                             : QueryStatus::separated;
  // Cores apart: move each witness out along the normal by its radius. If the radii overlap
  // (core distance < ra + rb) the moved points pass each other, dot(pb - pa, n) being minus the
  // penetration depth, and the distance clamps to 0.
  const VecN<D> n = delta * (1.0f / core_distance);
  pa += ra * n;
  pb -= rb * n;
  out.distance = std::max(core_distance - (ra + rb), 0.0f);
  out.point_a = transform_point(xa, pa);
  out.point_b = transform_point(xa, pb);
  out.normal = rotate(xa.q, n);
  return out;
}

template DistanceResultN<2> gjk_distance<2>(const ConvexProxyN<2>&, const Transform&,
                                            const ConvexProxyN<2>&, const Transform&,
                                            SimplexCacheN<2>*) noexcept;
template DistanceResultN<3> gjk_distance<3>(const ConvexProxyN<3>&, const Transform3&,
                                            const ConvexProxyN<3>&, const Transform3&,
                                            SimplexCacheN<3>*) noexcept;

DistanceResult distance(const Shape2D& a, const Transform& xa, const Shape2D& b,
                        const Transform& xb, SimplexCache* cache) noexcept {
  return std::visit(
      [&](const auto& sa, const auto& sb) { return distance(sa, xa, sb, xb, cache); }, a, b);
}

DistanceResult3 distance(const Shape3D& a, const Transform3& xa, const Shape3D& b,
                         const Transform3& xb, SimplexCache3* cache) noexcept {
  return std::visit(
      [&](const auto& sa, const auto& sb) { return distance(sa, xa, sb, xb, cache); }, a, b);
}

}  // namespace collide
