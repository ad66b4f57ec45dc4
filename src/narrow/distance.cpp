#include <collide/narrow/distance.hpp>

#include <collide/narrow/gjk.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include "point_region.hpp"
#include "sat_lanes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
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

/// The cached simplex, if its indices are valid for these proxies: its vertices with B placed
/// by `b_in_a`, cut to its first vertex when it is degenerate now (the shapes may have moved
/// since). False (nothing meaningful in `s`) for an invalid cache.
template <int D>
COLLIDE_ALWAYS_INLINE bool cached_simplex(const ConvexProxyN<D>& a, const ConvexProxyN<D>& b,
                                          const FrameN<D>& b_in_a, const SimplexCacheN<D>& cache,
                                          GjkSimplexN<D>& s) noexcept {
  const int cached = cache.count;
  bool valid = cached >= 1 && cached <= D + 1;
  for (int i = 0; i < cached && valid; ++i) {
    valid = cache.index_a[i] < a.count() && cache.index_b[i] < b.count();
  }
  if (!valid) return false;
  for (int i = 0; i < cached; ++i) {
    s.v[i] = gjk_vertex<D>(a, b, b_in_a, cache.index_a[i], cache.index_b[i]);
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
  return true;
}

/// The starting simplex: the cached one (cached_simplex) if valid, else the seed vertex
/// (gjk.hpp), which costs one support evaluation: `seeded` is then true.
template <int D>
COLLIDE_ALWAYS_INLINE GjkSimplexN<D> start_simplex(const ConvexProxyN<D>& a, const ConvexProxyN<D>& b,
                             const FrameN<D>& b_in_a, const SimplexCacheN<D>* cache,
                             bool& seeded) noexcept {
  GjkSimplexN<D> s;
  seeded = cache == nullptr || !cached_simplex<D>(a, b, b_in_a, *cache, s);
  if (seeded) {
    s.v[0] = gjk_seed_vertex<D>(a, b, b_in_a);
    s.count = 1;
  }
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

/// The answer for the simplex GJK ended on (`end`, after `iterations` support points): the
/// cache (if any) names its vertices, the witness points come from its barycentric weights,
/// and the result is in world space (A's frame placed by `xa`).
template <int D>
COLLIDE_ALWAYS_INLINE DistanceResultN<D> gjk_answer(const GjkSimplexN<D>& s, GjkEnd end, int iterations,
                                                    float ra, float rb, const TransformN<D>& xa,
                                                    SimplexCacheN<D>* cache) noexcept {
  DistanceResultN<D> out;
  out.iterations = iterations;
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
  int iterations = 0;
  const GjkEnd end = run_gjk<D>(a, b, b_in_a, s, scale, GjkRunToEnd{}, iterations);
  if (seeded) ++iterations;  // the seed's support evaluation counts as an iteration
  return gjk_answer<D>(s, end, iterations, ra, rb, xa, cache);
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

/// Features of two polygons' cores on the way to their closest pair: a corner of each (A's
/// vertex `first`, B's vertex `second`), or an edge of one (the "first": A's when `a_first`) and
/// a corner of the other.
struct Features {
  bool face = false;    ///< first is an edge (from vertex first to the next), else a corner
  bool a_first = true;  ///< first is A's (always, for a corner pair)
  int first = 0;
  int second = 0;
};

/// Most steps of walk_to_closest before it gives up (a cycle between features that rounding
/// can cause when a pair is all but degenerate).
inline constexpr int kMaxWalkSteps = 12;

/// Walks from `f` to the closest pair of the cores of A and B (Lin & Canny's closest-feature
/// walk, 1991, in 2D), true with the pair in `out`. A pair is closest when the line between
/// its points leaves both cores on their own sides: for an edge, the other corner's foot on
/// the edge and that corner the lowest of its polygon along the edge's normal; for two corners,
/// each the farthest of its polygon towards the other (the optimality condition of the
/// closest points of convex sets; Ericson, Real-Time Collision Detection, 9.1). Each failed
/// condition names the neighbouring feature that is closer: the edge the other corner lies
/// over, the corner an edge's foot falls beyond, the lower neighbour of a corner. False when a
/// corner lies within `on_core` of an edge's line or behind it (the cores may overlap: the
/// caller decides) or after kMaxWalkSteps. `b_in_a` places B in A's frame (from the world
/// placements `xa`, `xb`, which give A in B's frame when the walk meets one of B's edges).
/// Inlined by force: called, it saved and restored six registers and passed the pair back
/// through memory (a sixth of a warm-started query's instructions).
COLLIDE_ALWAYS_INLINE bool walk_to_closest(const Polygon& a, const Polygon& b, const Transform& xa,
                                           const Transform& xb, const Transform& b_in_a, float on_core,
                                           Features f, PolygonPair& out) noexcept {
  for (int step = 0; step < kMaxWalkSteps; ++step) {
    if (!f.face) {
      const Vec2 ak = a.vertices[f.first];
      const Vec2 w = transform_point(b_in_a, b.vertices[f.second]);
      const Vec2 d = w - ak;
      const int a_next = next_vertex(f.first, a.count);
      const int a_previous = previous_vertex(f.first, a.count);
      if (dot(d, a.vertices[a_next] - ak) > 0.0f) {  // B's corner lies over A's next edge
        f = {true, true, f.first, f.second};
        continue;
      }
      if (dot(d, a.vertices[a_previous] - ak) > 0.0f) {
        f = {true, true, a_previous, f.second};
        continue;
      }
      const Vec2 m = inv_rotate(b_in_a.q, d);  // B's corner should be lowest along d
      const Vec2 bv = b.vertices[f.second];
      const int b_next = next_vertex(f.second, b.count);
      const int b_previous = previous_vertex(f.second, b.count);
      if (dot(m, b.vertices[b_next] - bv) < 0.0f) {  // A's corner lies over B's next edge
        f = {true, false, f.second, f.first};
        continue;
      }
      if (dot(m, b.vertices[b_previous] - bv) < 0.0f) {
        f = {true, false, b_previous, f.first};
        continue;
      }
      const float gap = length(d);
      if (!(gap > on_core)) return false;
      out = {true, f.first, f.first, f.second, ak, w, d * (1.0f / gap), gap};
      return true;
    }
    // An edge of p (the first) and a corner of q, in p's frame.
    const Polygon& p = f.a_first ? a : b;
    const Polygon& q = f.a_first ? b : a;
    // (A in B's frame only when the edge is B's: most walks end on one of A's.)
    const Transform q_in_p = f.a_first ? b_in_a : inv_mul(xb, xa);
    const int end = next_vertex(f.first, p.count);
    const Vec2 n = p.normals[f.first];
    const Vec2 v1 = p.vertices[f.first];
    const Vec2 e = p.vertices[end] - v1;
    const Vec2 w = transform_point(q_in_p, q.vertices[f.second]);
    const Vec2 d = w - v1;
    const float gap = dot(n, d);
    if (!(gap > on_core)) return false;
    const float t = dot(d, e);
    const float ee = dot(e, e);
    // The foot falls beyond an end, or the edge has no length (a box of zero height repeats
    // its corners; t / ee would be 0 / 0): that corner.
    if (!(t >= 0.0f) || !(t <= ee) || !(ee > 0.0f)) {
      const int corner = t < 0.0f ? f.first : end;
      f = f.a_first ? Features{false, true, corner, f.second}
                    : Features{false, true, f.second, corner};
      continue;
    }
    const Vec2 m = inv_rotate(q_in_p.q, n);  // q's corner should be lowest along n
    const Vec2 qv = q.vertices[f.second];
    const int q_next = next_vertex(f.second, q.count);
    const int q_previous = previous_vertex(f.second, q.count);
    if (dot(m, q.vertices[q_next] - qv) < 0.0f) {
      f.second = q_next;
      continue;
    }
    if (dot(m, q.vertices[q_previous] - qv) < 0.0f) {
      f.second = q_previous;
      continue;
    }
    out = {f.a_first, f.first, end, f.second, v1 + (t / ee) * e, w, n, gap};
    return true;
  }
  return false;
}

/// The features a cache names, if they fit these polygons: a vertex of each, or an edge of one
/// (index_X[0] to [1] or back) and a vertex of the other.
bool cached_features(const SimplexCache& c, const Polygon& a, const Polygon& b,
                     Features& f) noexcept {
  const int a0 = c.index_a[0];
  const int a1 = c.index_a[1];
  const int b0 = c.index_b[0];
  const int b1 = c.index_b[1];
  if (c.count == 1) {
    f = {false, true, a0, b0};
    return a0 < a.count && b0 < b.count;
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
    f = {true, true, edge_of(a0, a1, a.count), b0};
    return f.first >= 0;
  }
  if (a0 == a1) {
    f = {true, false, edge_of(b0, b1, b.count), a0};
    return f.first >= 0;
  }
  return false;
}

/// For a cache naming a triangle of A - B (GJK's last answer: the cores overlapped): true with
/// that triangle in `s` when it still holds the origin, farther than `on_core` inside each of
/// its edges, and GJK's solver finds the origin inside it. The cores overlap then, so the walk
/// and the separating axes could only fail before GJK, which, started on this triangle, would
/// end on it at once; the caller answers from it (gjk_answer) as GJK would. A tenth of a
/// warm-started run's queries (bench_narrow_distance), each costing as much as four answered
/// by the walk.
bool cached_triangle_holds_origin(const Polygon& a, const Polygon& b, const Transform& b_in_a,
                                  const SimplexCache& c, float on_core, GjkSimplexN<2>& s) noexcept {
  if (!cached_simplex<2>(ConvexProxy(a), ConvexProxy(b), b_in_a, c, s) || s.count != 3) return false;
  // Each edge's cross product with the origin, signed so that inside is positive.
  const float orientation = cross(s.v[1].w - s.v[0].w, s.v[2].w - s.v[0].w);
  const float sign = orientation > 0.0f ? 1.0f : -1.0f;
  bool inside = orientation != 0.0f;
  for (int i = 0; i < 3; ++i) {
    const Vec2 w = s.v[i].w;
    const Vec2 e = s.v[i == 2 ? 0 : i + 1].w - w;
    const float side = sign * cross(e, -w);  // the origin's distance from the edge's line times |e|
    inside &= side > 0.0f && side * side > on_core * on_core * dot(e, e);
  }
  return inside && gjk_reduce(s);
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
COLLIDE_ALWAYS_INLINE DistanceResult pair_result(const PolygonPair& pair, float ra, float rb,
                                                 const Transform& xa, const Transform& xb,
                                                 SimplexCache* cache) noexcept {
  DistanceResult out;
  if (cache != nullptr) write_cache(pair, *cache);
  if (pair.a_first) {
    set_apart<2>(out, pair.on_first, pair.on_second, pair.normal, pair.gap, ra, rb, xa);
  } else {
    set_apart<2>(out, pair.on_second, pair.on_first, -pair.normal, pair.gap, ra, rb, xb);
  }
  return out;
}

}  // namespace

DistanceResult distance(const Polygon& a, const Transform& xa, const Polygon& b,
                        const Transform& xb, SimplexCache* cache) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "distance: transforms must be finite rigid");
  const Transform b_in_a = inv_mul(xa, xb);
  // GJK's overlap tolerance (gjk_scale): relative to the coordinates' size in A's frame.
  const float ra = a.radius;
  const float rb = b.radius;
  const float scale =
      std::max(max_abs(a.vertices[0]), max_abs(transform_point(b_in_a, b.vertices[0]))) + ra + rb;
  const float on_core = kRelativeTolerance * scale;

  if (cache != nullptr && cache->count == 3) {
    GjkSimplexN<2> s;
    if (cached_triangle_holds_origin(a, b, b_in_a, *cache, on_core, s)) {
      return gjk_answer<2>(s, GjkEnd::overlapped, 0, ra, rb, xa, cache);
    }
  }

  PolygonPair pair;
  const auto answer = [&]() { return pair_result(pair, ra, rb, xa, xb, cache); };
  // Walk from last frame's closest features, or on a cold start from GJK's first support pair
  // (gjk_seed_vertex: the corners farthest towards each other along the line between the
  // shapes' origins); the closest pair is usually there or a step or two away.
  Features start;
  if (cache == nullptr || !cached_features(*cache, a, b, start)) {
    const Vec2 c = b_in_a.p;
    start = dot(c, c) > 0.0f
                ? Features{false, true, ConvexProxy(a).support_index(c),
                           ConvexProxy(b).support_index(inv_rotate(b_in_a.q, -c))}
                : Features{};
  }
  if (walk_to_closest(a, b, xa, xb, b_in_a, on_core, start, pair)) return answer();

  SimplexCache seed;  // GJK's start: the user's cache, or the best axis's features
  if (cache != nullptr) seed = *cache;
#if COLLIDE_SMALL_POLYGON_SSE2
  // The walk met a corner behind an edge (the cores may overlap) or went round in circles: the
  // separating axes of both polygons (in registers, as the manifold's) tell overlap (no axis
  // separates: GJK gives the witness) from apart, where the best axis's edge and the other
  // core's lowest vertex along it start a walk that almost always ends at once.
  const detail::SharedFrame f{b_in_a, a.vertices[0], b_in_a.p - a.vertices[0]};
  bool found = false;
  detail::with_lane_groups(a.count, b.count, [&](auto groups_a, auto groups_b) {
    detail::LanePair<groups_a(), groups_b()> p;
    if (!detail::separate_lanes(a, b, f, std::numeric_limits<float>::infinity(), p)) return;
    if (!(std::max(p.sep_a.separation, p.sep_b.separation) > on_core)) return;  // GJK decides
    Features axis;
    if (p.sep_a.separation >= p.sep_b.separation) {
      axis = {true, true, p.sep_a.edge, detail::lowest_point(p.bv, a.normals[p.sep_a.edge])};
    } else {
      axis = {true, false, p.sep_b.edge,
              detail::lowest_point(p.av, rotate(b_in_a.q, b.normals[p.sep_b.edge]))};
    }
    found = walk_to_closest(a, b, xa, xb, b_in_a, on_core, axis, pair);
    if (!found) {
      const int edge_end = next_vertex(axis.first, axis.a_first ? a.count : b.count);
      write_cache({axis.a_first, axis.first, edge_end, axis.second}, seed);
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
/// 8 vertices four edges at a time in registers, else a scalar scan. Returns false when any
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
  bool ok = best == best;
  edge = 0;
  for (int i = 1; i < a.count; ++i) {
    const float s = dot(a.normals[i], c - a.vertices[i]);
    ok &= s == s;
    edge = s > best ? i : edge;
    best = s > best ? s : best;
  }
  return ok;
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

/// Polygon and circle in either order (A, B placed by xa, xb): the closest pair in the
/// polygon's frame (polygon_point_pair), GJK when the centre is on or inside the core.
template <class A, class B>
DistanceResult polygon_circle_distance(const A& a, const Transform& xa, const B& b,
                                       const Transform& xb, SimplexCache* cache) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "distance: transforms must be finite rigid");
  constexpr bool kPolygonFirst = std::is_same_v<A, Polygon>;
  const Polygon& p = [&]() -> const Polygon& {
    if constexpr (kPolygonFirst) return a; else return b;
  }();
  const Circle& circle = [&]() -> const Circle& {
    if constexpr (kPolygonFirst) return b; else return a;
  }();
  // The centre in the polygon's frame, relative positions formed first.
  const Vec2 c = kPolygonFirst ? transform_point(inv_mul(xa, xb), circle.center)
                               : transform_point(inv_mul(xb, xa), circle.center);
  // GJK's overlap tolerance (gjk_scale): relative to the coordinates' size in that frame.
  const float scale = std::max(max_abs(p.vertices[0]), max_abs(c)) + p.radius + circle.radius;
  PolygonPair pair;
  if (polygon_point_pair(p, c, kPolygonFirst, kRelativeTolerance * scale, pair)) {
    return pair_result(pair, a.radius, b.radius, xa, xb, cache);
  }
  return gjk_distance<2>(ConvexProxy(a), xa, ConvexProxy(b), xb, cache);
}

}  // namespace

DistanceResult distance(const Polygon& a, const Transform& xa, const Circle& b,
                        const Transform& xb, SimplexCache* cache) noexcept {
  return polygon_circle_distance(a, xa, b, xb, cache);
}

DistanceResult distance(const Circle& a, const Transform& xa, const Polygon& b,
                        const Transform& xb, SimplexCache* cache) noexcept {
  return polygon_circle_distance(a, xa, b, xb, cache);
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
