#include <collide/narrow/distance.hpp>

#include <collide/narrow/gjk.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include "point_region.hpp"
#include "sat_lanes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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

/// Fills `out` for cores apart by `core_distance` > 0 with core witnesses `pa`, `pb` and unit
/// normal `n` from A to B, all in the frame that `x` places in the world: each witness moves
/// out along the normal by its radius. If the radii overlap (core distance < ra + rb) the moved
/// points pass each other, dot(pb - pa, n) being minus the penetration depth, and the distance
/// clamps to 0.
template <int D>
COLLIDE_ALWAYS_INLINE void set_apart(DistanceResultN<D>& out, VecN<D> pa, VecN<D> pb, VecN<D> n,
                                     float core_distance, float ra, float rb,
                                     const TransformN<D>& x) noexcept {
  pa += ra * n;
  pb -= rb * n;
  out.distance = std::max(core_distance - (ra + rb), 0.0f);
  out.point_a = transform_point(x, pa);
  out.point_b = transform_point(x, pb);
  out.normal = rotate(x.q, n);
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
  set_apart<D>(out, pa, pb, delta * (1.0f / core_distance), core_distance, ra, rb, xa);
  return out;
}

template DistanceResultN<2> gjk_distance<2>(const ConvexProxyN<2>&, const Transform&,
                                            const ConvexProxyN<2>&, const Transform&,
                                            SimplexCacheN<2>*) noexcept;
template DistanceResultN<3> gjk_distance<3>(const ConvexProxyN<3>&, const Transform3&,
                                            const ConvexProxyN<3>&, const Transform3&,
                                            SimplexCacheN<3>*) noexcept;

namespace {

/// A closest pair of the cores of two polygons, seen from one of them (the "first"; the other is
/// the "second"), in the first's frame: an edge of the first and a vertex of the second, or a
/// vertex of each (corner against corner).
struct PolygonPair {
  bool a_first = true;     ///< the first polygon is A
  int first0 = 0;          ///< the first's feature: edge first0 (first1 = its next vertex) ...
  int first1 = 0;          ///< ... or vertex first0 (first1 == first0)
  int second = 0;          ///< the second's vertex
  Vec2 on_first{0.0f};     ///< closest core point of the first
  Vec2 on_second{0.0f};    ///< closest core point of the second (its vertex)
  Vec2 normal{0.0f};       ///< unit, from the first to the second
  float gap = 0.0f;        ///< distance between the cores, > 0
};

[[nodiscard]] constexpr int next_vertex(int i, int n) noexcept { return i + 1 == n ? 0 : i + 1; }
[[nodiscard]] constexpr int previous_vertex(int i, int n) noexcept { return i == 0 ? n - 1 : i - 1; }

/// Whether vertex `v` of polygon `q` is its lowest point along `m` (q's frame): on a convex
/// polygon, when neither neighbour is lower.
COLLIDE_ALWAYS_INLINE bool lowest_along(const Polygon& q, int v, Vec2 m) noexcept {
  const Vec2 qv = q.vertices[v];
  return dot(m, q.vertices[previous_vertex(v, q.count)] - qv) >= 0.0f &&
         dot(m, q.vertices[next_vertex(v, q.count)] - qv) >= 0.0f;
}

/// Whether edge `edge` of polygon `p` and vertex `v` of polygon `q` (placed in p's frame by
/// `q_in_p`) are a closest pair of the cores, and if so the pair in `out`. They are when the
/// vertex is beyond the edge's line by more than `on_core`, its foot lies on the edge, and
/// (unless `v_is_lowest`: the caller found it as q's lowest point along the normal) it is q's
/// lowest point along the edge's normal: then the strip between the edge's line and the
/// parallel line through the vertex holds neither core, so no pair is closer than its width,
/// which this pair attains (the optimality condition of the closest points of two convex sets,
/// Ericson, Real-Time Collision Detection, 9.1; its separating axis, 5.2.1).
COLLIDE_ALWAYS_INLINE bool face_pair(const Polygon& p, int edge, const Polygon& q, int v, const Transform& q_in_p,
               bool a_first, float on_core, bool v_is_lowest, PolygonPair& out) noexcept {
  const Vec2 n = p.normals[edge];
  if (!v_is_lowest && !lowest_along(q, v, inv_rotate(q_in_p.q, n))) return false;
  const int end = next_vertex(edge, p.count);
  const Vec2 v1 = p.vertices[edge];
  const Vec2 e = p.vertices[end] - v1;
  const Vec2 w = transform_point(q_in_p, q.vertices[v]);
  const Vec2 d = w - v1;
  const float gap = dot(n, d);
  const float t = dot(d, e);
  const float ee = dot(e, e);
  if (!(gap > on_core) || !(t >= 0.0f) || !(t <= ee)) return false;
  out = {a_first, edge, end, v, v1 + (t / ee) * e, w, n, gap};
  return true;
}

/// Whether vertex `k` of polygon `p` and vertex `v` of polygon `q` (placed in p's frame by
/// `q_in_p`) are a closest pair of the cores: more than `on_core` apart, p's vertex the highest
/// of p and q's the lowest of q along the line between them (same condition as face_pair).
COLLIDE_ALWAYS_INLINE bool corner_pair(const Polygon& p, int k, const Polygon& q, int v, const Transform& q_in_p,
                 bool a_first, float on_core, PolygonPair& out) noexcept {
  const Vec2 pk = p.vertices[k];
  const Vec2 w = transform_point(q_in_p, q.vertices[v]);
  const Vec2 d = w - pk;
  if (!(dot(d, p.vertices[previous_vertex(k, p.count)] - pk) <= 0.0f) ||
      !(dot(d, p.vertices[next_vertex(k, p.count)] - pk) <= 0.0f) ||
      !lowest_along(q, v, inv_rotate(q_in_p.q, d))) {
    return false;
  }
  const float gap = length(d);
  if (!(gap > on_core)) return false;
  out = {a_first, k, k, v, pk, w, d * (1.0f / gap), gap};
  return true;
}

/// Writes the simplex GJK would end on for `pair` into `c`: its vertex pairs (A's, B's). Field
/// by field: a cache built on the stack and copied whole was read back across its byte stores,
/// which the CPU cannot forward (a stall of a dozen cycles on every call).
void write_cache(const PolygonPair& pair, SimplexCache& c) noexcept {
  const auto f0 = static_cast<std::uint8_t>(pair.first0);
  const auto f1 = static_cast<std::uint8_t>(pair.first1);
  const auto s = static_cast<std::uint8_t>(pair.second);
  c.count = pair.first0 == pair.first1 ? 1 : 2;
  c.index_a[0] = pair.a_first ? f0 : s;
  c.index_a[1] = pair.a_first ? f1 : s;
  c.index_b[0] = pair.a_first ? s : f0;
  c.index_b[1] = pair.a_first ? s : f1;
}

/// The distance result for a closest pair of cores, with the radii `ra`, `rb` applied, in world
/// space; `cache` (if any) names the pair.
COLLIDE_ALWAYS_INLINE DistanceResult pair_result(const PolygonPair& pair, float ra, float rb, const Transform& xa,
                           const Transform& xb, SimplexCache* cache) noexcept {
  DistanceResult out;
  if (cache != nullptr) write_cache(pair, *cache);
  if (pair.a_first) {
    set_apart<2>(out, pair.on_first, pair.on_second, pair.normal, pair.gap, ra, rb, xa);
  } else {
    set_apart<2>(out, pair.on_second, pair.on_first, -pair.normal, pair.gap, ra, rb, xb);
  }
  return out;
}

/// Whether the pair a cache names (a vertex of each, or an edge of one, index_X[0] to [1] or
/// back, and a vertex of the other) is still a closest pair.
bool cached_pair(const SimplexCache& c, const Polygon& a, const Polygon& b, const Transform& b_in_a,
                 const Transform& a_in_b, float on_core, PolygonPair& out) noexcept {
  const int a0 = c.index_a[0];
  const int a1 = c.index_a[1];
  const int b0 = c.index_b[0];
  const int b1 = c.index_b[1];
  if (c.count == 1) {
    return a0 < a.count && b0 < b.count && corner_pair(a, a0, b, b0, b_in_a, true, on_core, out);
  }
  if (c.count != 2 || a0 >= a.count || a1 >= a.count || b0 >= b.count || b1 >= b.count) {
    return false;
  }
  // The edge's first vertex, or -1 if i0, i1 are not an edge of an n-gon.
  const auto edge_of = [](int i0, int i1, int n) {
    if (i1 == next_vertex(i0, n)) return i0;
    return i0 == next_vertex(i1, n) ? i1 : -1;
  };
  if (b0 == b1) {
    const int edge = edge_of(a0, a1, a.count);
    return edge >= 0 && face_pair(a, edge, b, b0, b_in_a, true, on_core, false, out);
  }
  if (a0 == a1) {
    const int edge = edge_of(b0, b1, b.count);
    return edge >= 0 && face_pair(b, edge, a, a0, a_in_b, false, on_core, false, out);
  }
  return false;
}

/// From the best separating axis's features (edge `edge` of p, q's lowest vertex `v` along its
/// normal), the closest pair when it is one of them or next to them: the edge and the vertex;
/// else the corner of the edge the vertex's foot falls beyond against the vertex; else that
/// corner's other edge against the vertex, or the vertex's two edges against the corner.
bool pair_near_axis(const Polygon& p, int edge, const Polygon& q, int v, const Transform& q_in_p,
                    const Transform& p_in_q, bool a_first, float on_core,
                    PolygonPair& out) noexcept {
  if (face_pair(p, edge, q, v, q_in_p, a_first, on_core, true, out)) return true;
  const int end = next_vertex(edge, p.count);
  const Vec2 v1 = p.vertices[edge];
  const Vec2 w = transform_point(q_in_p, q.vertices[v]);
  const bool before = dot(w - v1, p.vertices[end] - v1) < 0.0f;
  const int k = before ? edge : end;           // the corner the foot falls beyond
  const int other = before ? previous_vertex(edge, p.count) : end;  // its other edge
  return corner_pair(p, k, q, v, q_in_p, a_first, on_core, out) ||
         face_pair(p, other, q, v, q_in_p, a_first, on_core, false, out) ||
         face_pair(q, v, p, k, p_in_q, !a_first, on_core, false, out) ||
         face_pair(q, previous_vertex(v, q.count), p, k, p_in_q, !a_first, on_core, false, out);
}

/// The closest pair when it is at or next to corner `k` of A and corner `v` of B: the corners
/// themselves, or an edge at one against the other's corner.
bool pair_near_corners(const Polygon& a, int k, const Polygon& b, int v, const Transform& b_in_a,
                       const Transform& a_in_b, float on_core, PolygonPair& out) noexcept {
  return corner_pair(a, k, b, v, b_in_a, true, on_core, out) ||
         face_pair(a, k, b, v, b_in_a, true, on_core, false, out) ||
         face_pair(a, previous_vertex(k, a.count), b, v, b_in_a, true, on_core, false, out) ||
         face_pair(b, v, a, k, a_in_b, false, on_core, false, out) ||
         face_pair(b, previous_vertex(v, b.count), a, k, a_in_b, false, on_core, false, out);
}

}  // namespace

DistanceResult distance(const Polygon& a, const Transform& xa, const Polygon& b,
                        const Transform& xb, SimplexCache* cache) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "distance: transforms must be finite rigid");
  const Transform b_in_a = inv_mul(xa, xb);
  const Transform a_in_b = inv_mul(xb, xa);
  // GJK's overlap tolerance (gjk_scale): relative to the coordinates' size in A's frame.
  const float ra = a.radius;
  const float rb = b.radius;
  const float scale =
      std::max(max_abs(a.vertices[0]), max_abs(transform_point(b_in_a, b.vertices[0]))) + ra + rb;
  const float on_core = kRelativeTolerance * scale;

  PolygonPair pair;
  const auto answer = [&]() { return pair_result(pair, ra, rb, xa, xb, cache); };
  // Warm start: last frame's closest features, if they are still a closest pair.
  if (cache != nullptr && cached_pair(*cache, a, b, b_in_a, a_in_b, on_core, pair)) {
    return answer();
  }

  // GJK's first support pair: the corners farthest towards each other along the line between
  // the shapes' origins (gjk_seed_vertex). The closest pair is usually at or next to them.
  const Vec2 c = b_in_a.p;
  if (dot(c, c) > 0.0f) {
    const int k = ConvexProxy(a).support_index(c);
    const int v = ConvexProxy(b).support_index(inv_rotate(b_in_a.q, -c));
    if (pair_near_corners(a, k, b, v, b_in_a, a_in_b, on_core, pair)) return answer();
  }

  SimplexCache seed;  // GJK's start: the user's cache, or the best axis's features
  if (cache != nullptr) seed = *cache;
#if COLLIDE_SMALL_POLYGON_SSE2
  // The separating axes of both polygons (in registers, as the manifold's); the closest pair
  // is then almost always the best axis's edge and the other core's lowest vertex along it, or
  // next to them (pair_near_axis). If not, GJK starts from those features.
  const detail::SharedFrame f{b_in_a, a.vertices[0], b_in_a.p - a.vertices[0]};
  bool found = false;
  detail::with_lane_groups(a.count, b.count, [&](auto groups_a, auto groups_b) {
    detail::LanePair<groups_a(), groups_b()> p;
    if (!detail::separate_lanes(a, b, f, std::numeric_limits<float>::infinity(), p)) return;
    const bool a_face = p.sep_a.separation >= p.sep_b.separation;
    if (!(std::max(p.sep_a.separation, p.sep_b.separation) > on_core)) return;  // GJK decides
    int edge = 0;
    int vertex = 0;
    if (a_face) {
      edge = p.sep_a.edge;
      vertex = detail::lowest_point(p.bv, a.normals[edge]);
      found = pair_near_axis(a, edge, b, vertex, b_in_a, a_in_b, true, on_core, pair);
    } else {
      edge = p.sep_b.edge;
      vertex = detail::lowest_point(p.av, rotate(b_in_a.q, b.normals[edge]));
      found = pair_near_axis(b, edge, a, vertex, a_in_b, b_in_a, false, on_core, pair);
    }
    if (!found) {
      PolygonPair axis;
      axis.a_first = a_face;
      axis.first0 = edge;
      axis.first1 = next_vertex(edge, a_face ? a.count : b.count);
      axis.second = vertex;
      write_cache(axis, seed);
    }
  });
  if (found) return answer();
#endif
  const DistanceResult out = gjk_distance<2>(ConvexProxy(a), xa, ConvexProxy(b), xb, &seed);
  if (cache != nullptr) *cache = seed;
  return out;
}

namespace {

/// The edge of `a` (its frame) of greatest separation dot(n_i, c - v_i) of point `c`: for up to
/// 8 vertices four edges at a time in registers, else a scalar scan. Returns false when a
/// separation is NaN.
bool max_point_separation(const Polygon& a, Vec2 c, int& edge) noexcept {
#if COLLIDE_SMALL_POLYGON_SSE2
  if (a.count <= 2 * detail::kSatLanes) {
    // The point in every lane, from registers (a load of it would read across the two stores
    // that just wrote it, which the CPU cannot forward).
    const detail::LanePoints<1> point{{_mm_set1_ps(c.x)}, {_mm_set1_ps(c.y)}};
    EdgeSeparation best;
    bool ok = false;
    detail::with_lane_groups(a.count, 1, [&](auto groups_a, auto) {
      const auto normals = detail::load_points<groups_a()>(a.normals.data(), a.count);
      const auto vertices = detail::load_points<groups_a()>(a.vertices.data(), a.count);
      ok = detail::max_separation_lanes(normals, vertices, point, best);
    });
    edge = best.edge;
    return ok;
  }
#endif
  float best = dot(a.normals[0], c - a.vertices[0]);
  edge = 0;
  for (int i = 1; i < a.count; ++i) {
    const float s = dot(a.normals[i], c - a.vertices[i]);
    edge = s > best ? i : edge;
    best = s > best ? s : best;
  }
  return best == best;
}

/// The closest pair of polygon `p`'s core and point `c` (p's frame), seen from p (`a_first`:
/// p is A): the Voronoi region of c, the edge of greatest separation or one of its ends.
/// False when c is within `on_core` of the core or inside it, or a separation is NaN.
COLLIDE_ALWAYS_INLINE bool polygon_point_pair(const Polygon& p, Vec2 c, bool a_first,
                                              float on_core, PolygonPair& out) noexcept {
  int edge = 0;
  if (!max_point_separation(p, c, edge)) return false;
  const Vec2 n = p.normals[edge];
  const float separation = dot(n, c - p.vertices[edge]);
  if (!(separation > on_core)) return false;
  const int next = next_vertex(edge, p.count);
  const int end = detail::edge_end_region(p, edge, next, c);
  if (end < 0) {
    out = {a_first, edge, next, 0, c - separation * n, c, n, separation};
    return true;
  }
  const Vec2 d = c - p.vertices[end];
  const float gap = length(d);
  if (!(gap > on_core)) return false;
  out = {a_first, end, end, 0, p.vertices[end], c, d * (1.0f / gap), gap};
  return true;
}

}  // namespace

DistanceResult distance(const Polygon& a, const Transform& xa, const Circle& b,
                        const Transform& xb, SimplexCache* cache) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "distance: transforms must be finite rigid");
  const Vec2 c = transform_point(inv_mul(xa, xb), b.center);  // B's centre, A's frame
  // GJK's overlap tolerance (gjk_scale): relative to the coordinates' size in A's frame.
  const float scale = std::max(max_abs(a.vertices[0]), max_abs(c)) + a.radius + b.radius;
  PolygonPair pair;
  if (polygon_point_pair(a, c, true, kRelativeTolerance * scale, pair)) {
    return pair_result(pair, a.radius, b.radius, xa, xb, cache);
  }
  // The centre on or inside the core: GJK's answer (one point inside both).
  return gjk_distance<2>(ConvexProxy(a), xa, ConvexProxy(b), xb, cache);
}

DistanceResult distance(const Circle& a, const Transform& xa, const Polygon& b,
                        const Transform& xb, SimplexCache* cache) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "distance: transforms must be finite rigid");
  const Vec2 c = transform_point(inv_mul(xb, xa), a.center);  // A's centre, B's frame
  const float scale = std::max(max_abs(b.vertices[0]), max_abs(c)) + a.radius + b.radius;
  PolygonPair pair;
  if (polygon_point_pair(b, c, false, kRelativeTolerance * scale, pair)) {
    return pair_result(pair, a.radius, b.radius, xa, xb, cache);
  }
  return gjk_distance<2>(ConvexProxy(a), xa, ConvexProxy(b), xb, cache);
}

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
