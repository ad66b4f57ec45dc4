// Ray casts against single 2D shapes.
//
// Every cast first moves the ray into the shape's local frame (subtract the position, then undo
// the rotation), so a shape and a ray 1e4 units from the world origin lose no more precision
// than the same pair at the origin. All work is then local; the normal is rotated back once.
//
// Convention shared by all shapes: the ray must *enter* the shape. A ray whose origin lies in
// the closed shape (inside, or on the surface) reports no hit, and so does a ray of zero length.

#include <collide/ccd/raycast.hpp>

#include <collide/core/config.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/closest_point.hpp>

#include "clip_ray.hpp"
#include "ray_ball.hpp"
#include "rounded_polygon_ray.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

// SSE2 is part of every x86-64 CPU; elsewhere the scalar loops run (define
// COLLIDE_RAYCAST_SSE2=0 to run them on x86 too).
#ifndef COLLIDE_RAYCAST_SSE2
#if defined(__SSE2__) || defined(_M_X64)
#define COLLIDE_RAYCAST_SSE2 1
#else
#define COLLIDE_RAYCAST_SSE2 0
#endif
#endif
#if COLLIDE_RAYCAST_SSE2
#include <emmintrin.h>
#endif

namespace collide {
namespace {

using LocalHit = detail::LocalHitN<2>;

/// The local ray: origin and translation in the shape's frame.
struct LocalRay {
  Vec2 origin;
  Vec2 translation;
};

LocalRay to_local(const Transform& xf, const Ray& ray) noexcept {
  return {inv_transform_point(xf, ray.origin), inv_rotate(xf.q, ray.translation)};
}

RayHit to_world(const LocalHit& h, const Transform& xf, const Ray& ray) noexcept {
  if (!h.hit) return {};
  return {true, h.fraction, ray.at(h.fraction), rotate(xf.q, h.normal)};
}

/// The hit of `h` on `ray` when its normal is already in world space (raycast3.cpp's world_hit
/// in 2D). Without a branch on whether it hit (random rays hit or miss at random; ray_ball's
/// reason): a miss's point is zeroed by a mask, its other fields are zero already.
RayHit world_hit(const LocalHit& h, const Ray& ray) noexcept {
  const std::uint32_t keep = detail::mask_of(h.hit);
  const Vec2 point = ray.at(h.fraction);
  return {h.hit, h.fraction, {detail::keep_if(point.x, keep), detail::keep_if(point.y, keep)}, h.normal};
}

/// First entry into the disc of `radius` about the origin: the ball entry of ray_ball.hpp.
inline LocalHit ray_disc(Vec2 m, Vec2 d, float radius) noexcept {
  return detail::ray_ball<2>(m, d, radius);
}

/// Where a ray enters a convex polygon, in its local frame (`plane` is the entering edge).
using Clip = detail::ClipResult;

/// Cyrus-Beck clipping of p + t d, t in [0, 1], against the half-planes
/// n_i . (x - v_i) <= offset of a convex outline (clip_ray.hpp). offset r is the outline with
/// every edge pushed out by r (used for rounded polygons).
COLLIDE_ALWAYS_INLINE Clip clip_ray_outline(const detail::OutlineView& o, Vec2 p, Vec2 d,
                                            float offset) noexcept {
#if defined(__SSE2__) || defined(_M_X64)
  return detail::clip_ray_outline_lanes(o.vertices, o.normals, o.count, p, d, offset);
#else
  return detail::clip_ray(o.count, [&](int i) {
    const Vec2 normal = o.normals[i];
    return detail::PlaneCrossing{offset - dot(normal, p - o.vertices[i]), dot(normal, d)};
  });
#endif
}

/// Capsule: the union of the band |y| <= r over 0 <= x <= L along its axis (x from a towards b,
/// y to the left) and the two end discs (Ericson, Real-Time Collision Detection, 5.3.7 in 2D).
/// If the ray starts above or below the band, it can only enter through the flat side facing
/// it or, when it crosses that side's line beyond an end, through that end's disc (to reach the
/// band from there it has to pass through the disc). If it starts level with the band, only
/// the disc on its side can be first. The axis coordinates are kept scaled by L (dot and cross
/// products with b - a, bounds L r and L^2), so no square root or division stands between the
/// ray and the first test, and the cases are chosen by selects rather than branches: random
/// rays take each at random (bench_ray_cast, visited in an unlearnable order: 34 -> 31 ns). The
/// disc is cast in the local frame.
LocalHit raycast_local(const Capsule& capsule, Vec2 p, Vec2 d) noexcept {
  using detail::pick;
  const Vec2 axis = capsule.b - capsule.a;
  const float ll = length_squared(axis);
  const float length = std::sqrt(ll);  // off the critical path until the side's bound
  const float r = capsule.radius;
  const Vec2 rel = p - capsule.a;
  const float px = dot(rel, axis);    // L x
  const float py = cross(axis, rel);  // L y
  const float rl = r * length;        // the band's half width, scaled
  // The flat side facing the origin, y = side r: crossed at t_side, at x_side (scaled).
  const bool above = std::fabs(py) > rl;
  const float side = pick(py > 0.0f, 1.0f, -1.0f);
  const float dy = cross(axis, d);
  const float t_side = (py - side * rl) / -dy;
  const float x_side = px + t_side * dot(d, axis);
  const bool reaches = (side * dy < 0.0f) & (t_side <= 1.0f);  // towards the side, in time
  const bool side_hit = above & reaches & (x_side >= 0.0f) & (x_side <= ll);
  // Otherwise the disc at the end on the side of where the ray meets the band (or of the origin,
  // level with it); none if it starts inside the band between the ends, or above it and never
  // reaches its line. Which end, from the sign of x_side without waiting for the division:
  // x_side times -dy, and -dy has the sign of `side` wherever the ray reaches the side.
  const float x_side_scaled = px * -dy + (py - side * rl) * dot(d, axis);
  const bool at_a = above ? side * x_side_scaled < 0.0f : px < 0.0f;
  const Vec2 centre{pick(at_a, capsule.a.x, capsule.b.x), pick(at_a, capsule.a.y, capsule.b.y)};
  const LocalHit disc = ray_disc(p - centre, d, r);
  const bool inside_band = !above & (px >= 0.0f) & (px <= ll);
  const bool disc_hit = disc.hit & !inside_band & !(above & !reaches);
  const bool hit = side_hit | disc_hit;
  const std::uint32_t keep = detail::mask_of(hit);
  const Vec2 side_normal = left_perp(axis) * (side / length);
  LocalHit h;
  h.hit = hit;
  h.fraction = detail::keep_if(pick(side_hit, t_side, disc.fraction), keep);
  h.normal = {detail::keep_if(pick(side_hit, side_normal.x, disc.normal.x), keep),
              detail::keep_if(pick(side_hit, side_normal.y, disc.normal.y), keep)};
  return h;
}

/// cast_sides' answer: `edge` is -1 when the ray's line misses the polygon; otherwise the edge
/// where the line enters, and `hit` says whether the ray gets there (`fraction` in (0, 1]; when
/// not `hit`, `fraction` is to be ignored: it may be NaN).
struct SideCast {
  float fraction;
  int edge;
  bool hit;
};

/// Entry of p + t d, t in [0, 1], into a convex polygon (no radius), by the sides of the ray's
/// line. Vertex i is left of the line when w_i = cross(d, v_i - p) > 0, right when w_i < 0. A
/// convex outline crosses a line twice; walking counter-clockwise it crosses from left to right
/// where the line enters (right to left where it exits). So the entering edge i is one that
/// leaves the left side (left_i and not left_{i+1}) or arrives on the right side (not right_i
/// and right_{i+1}), and the ray enters there at t = cross(v_i - p, e_i) / cross(d, e_i), which
/// must lie in (0, 1]: t <= 0 means p is already past the entry (inside, or beyond the
/// polygon). No such edge: the line misses. A line along an edge or through a corner enters at
/// that edge or corner (touching counts); a zero-length ray has no vertex on either side: miss.
///
/// Cheaper than clipping by every edge (Cyrus-Beck): one cross product per vertex, no normals
/// read, one division. The sides are gathered as bit masks and the edge found by counting
/// trailing zeros, so the scan has no data-dependent branch for random rays to mispredict.
SideCast cast_sides(const Polygon& poly, Vec2 p, Vec2 d) noexcept {
  static_assert(kMaxPolygonVertices <= 64, "side masks hold one bit per vertex");
  const int n = poly.count;
  // Bit i of left / right: w_i > 0 / w_i < 0, where w_i > 0 <=> cross(d, v_i) > cross(d, p).
  const float c = cross(d, p);
  std::uint64_t left = 0;
  std::uint64_t right = 0;
  int i = 0;
#if COLLIDE_RAYCAST_SSE2
  // Four vertices at a time, the same arithmetic as the scalar loop below (bench/ray_cast.cpp:
  // 8-gons 31 -> 20 ns, 4-gons 23 -> 18 ns). Vertices are stored x0 y0 x1 y1 ...: two loads and
  // two shuffles give the x and y of four vertices, compare masks give four side bits at once.
  const __m128 dx = _mm_set1_ps(d.x);
  const __m128 dy = _mm_set1_ps(d.y);
  const __m128 cc = _mm_set1_ps(c);
  for (; i + 4 <= n; i += 4) {
    const __m128 v01 = _mm_loadu_ps(&poly.vertices[i].x);
    const __m128 v23 = _mm_loadu_ps(&poly.vertices[i + 2].x);
    const __m128 xs = _mm_shuffle_ps(v01, v23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 ys = _mm_shuffle_ps(v01, v23, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 k = _mm_sub_ps(_mm_mul_ps(dx, ys), _mm_mul_ps(dy, xs));
    left |= static_cast<std::uint64_t>(_mm_movemask_ps(_mm_cmpgt_ps(k, cc))) << i;
    right |= static_cast<std::uint64_t>(_mm_movemask_ps(_mm_cmplt_ps(k, cc))) << i;
  }
#endif
  for (; i < n; ++i) {
    const float k = cross(d, poly.vertices[i]);
    left |= static_cast<std::uint64_t>(k > c) << i;
    right |= static_cast<std::uint64_t>(k < c) << i;
  }
  // Bit i of next_*: the side of vertex i + 1 (vertex 0 for the last edge).
  const int last = n - 1;
  const std::uint64_t next_left = (left >> 1) | ((left & 1u) << last);
  const std::uint64_t next_right = (right >> 1) | ((right & 1u) << last);
  const std::uint64_t enters = (left & ~next_left) | (~right & next_right);
  const std::uint64_t in_range = n == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1u;
  const std::uint64_t edges = enters & in_range;
  if (edges == 0) return {0.0f, -1, false};
  const int edge = std::countr_zero(edges);
  const Vec2 v = poly.vertices[edge];
  const Vec2 e = poly.vertices[edge < last ? edge + 1 : 0] - v;
  const float t = cross(v - p, e) / cross(d, e);  // cross(d, e) = w_{i+1} - w_i < 0
  // Whether t lies in (0, 1] without a branch: random rays stop short or reach the edge at
  // random, and the mispredicted return cost more than the work it skipped.
  const unsigned hit = unsigned{t > 0.0f} & unsigned{t <= 1.0f};
  return {t, edge, hit != 0};
}

/// Rounded polygon (radius > 0). Out of line: inlined, its registers were saved on entry to
/// every polygon cast (bench/ray_cast, 4-gons 20.5 -> 19.6-20.1 ns, 8-gons 26.5 -> 22.5-23).
[[gnu::noinline]] LocalHit raycast_rounded(const Polygon& poly, Vec2 p, Vec2 d) noexcept {
  return detail::ray_rounded_polygon(poly, poly.radius, p, d).hit;
}

/// Two-sided segment. The ray crosses the segment's line at t = -side / den, where side is the
/// origin's signed distance to the line (times the length) and den the rate of change.
/// Collinear rays (parallel within kParallelTolerance and on the line within
/// kRelativeTolerance of the length) hit the nearer end, facing the ray, since touching counts.
LocalHit raycast_local(const Segment& seg, Vec2 p, Vec2 d) noexcept {
  const Vec2 e = seg.b - seg.a;
  const Vec2 rel = p - seg.a;
  const float side = cross(e, rel);  // > 0: origin to the left of a -> b
  const float den = cross(e, d);
  const float ee = length_squared(e);
  const float dd = length_squared(d);
  if (!(dd > 0.0f)) return {};
  const bool parallel = den * den <= kParallelTolerance * kParallelTolerance * ee * dd;
  const bool on_line = side * side <= kRelativeTolerance * kRelativeTolerance * ee * ee;
  if (parallel && on_line) {
    // Along the line: parameters on the segment of the origin (s0) and its rate (ds).
    const float s0 = dot(rel, e) / ee;
    const float ds = dot(d, e) / ee;
    if (s0 < 0.0f && ds > 0.0f && -s0 <= ds) return {true, -s0 / ds, -e * (1.0f / std::sqrt(ee))};
    if (s0 > 1.0f && ds < 0.0f && s0 - 1.0f <= -ds) {
      return {true, (s0 - 1.0f) / -ds, e * (1.0f / std::sqrt(ee))};
    }
    return {};  // heading away, too short, or starting on the segment
  }
  // Must start strictly off the line and move towards it: side and den of opposite signs.
  if (!(side * den < 0.0f)) return {};
  const float t = -side / den;
  if (!(t <= 1.0f)) return {};
  // Where along the segment it crosses: s = cross(rel, d) / cross(e, d), must be in [0, 1].
  const float s = cross(rel, d) / den;
  if (!(s >= 0.0f && s <= 1.0f)) return {};
  const Vec2 right = right_perp(e) * (1.0f / std::sqrt(ee));
  return {true, t, side < 0.0f ? right : -right};
}

RayHit raycast_placed(const Polygon& poly, const Transform& xf, const Ray& ray) noexcept {
  const LocalRay local = to_local(xf, ray);
  if (poly.radius > 0.0f) {
    if (!(length_squared(local.translation) > 0.0f)) return {};
    return to_world(raycast_rounded(poly, local.origin, local.translation), xf, ray);
  }
  const SideCast cast = cast_sides(poly, local.origin, local.translation);
  if (cast.edge < 0) return {};
  // The edge's stored unit normal: with 8 vertices inline it sits one cache line past the
  // vertices (when normals lived 512 bytes away, recomputing it from the edge was faster).
  // A ray short of the edge zeroes every field by a mask rather than a branch (a select of the
  // whole struct compiled to a branch and a copy through the stack). bench/ray_cast against the
  // branch on t and the clip for boxes: 4-gons 38 -> 20 ns, 8-gons 21.7 -> 22.5-23 (Intel Xeon,
  // one A/B). Hosts differ here: on the AMD host of stop 39 a wholly branch-free end (no early
  // return for a missed line either) lost, 10.4 -> 15 ns; the missed line keeps its return.
  const std::uint32_t keep = detail::mask_of(cast.hit);
  const auto masked = [keep](float x) { return detail::keep_if(x, keep); };
  const float t = masked(cast.fraction);
  const Vec2 point = ray.at(t);
  const Vec2 normal = rotate(xf.q, poly.normals[cast.edge]);
  return {cast.hit, t, {masked(point.x), masked(point.y)}, {masked(normal.x), masked(normal.y)}};
}

/// Shapes with corners: cast in the local frame, rotate the normal back.
template <class S>
RayHit raycast_placed(const S& shape, const Transform& xf, const Ray& ray) noexcept {
  const LocalRay local = to_local(xf, ray);
  if (!(length_squared(local.translation) > 0.0f)) return {};
  return to_world(raycast_local(shape, local.origin, local.translation), xf, ray);
}

/// A capsule is cast in a frame turned as the world and centred on its placement, as in 3D
/// (raycast3.cpp): its ends are rotated there (two rotations) instead of the ray into its frame
/// and the normal back out (three), and the origin is made relative as (origin - p) so that
/// large coordinates cancel first. The normal comes out in world space (bench_ray_cast, capsules
/// visited in an unlearnable order, AMD EPYC: 41 -> 33 ns a cast).
RayHit raycast_placed(const Capsule& capsule, const Transform& xf, const Ray& ray) noexcept {
  if (!(length_squared(ray.translation) > 0.0f)) return {};
  const Capsule turned{rotate(xf.q, capsule.a), rotate(xf.q, capsule.b), capsule.radius};
  return world_hit(raycast_local(turned, ray.origin - xf.p, ray.translation), ray);
}

/// A disc looks the same in every frame: only the origin needs to be made relative to the
/// centre, as (origin - p) - R c so that large coordinates cancel first. No rotation of the
/// ray or the normal.
RayHit raycast_placed(const Circle& circle, const Transform& xf, const Ray& ray) noexcept {
  const Vec2 m = (ray.origin - xf.p) - rotate(xf.q, circle.center);
  return world_hit(ray_disc(m, ray.translation, circle.radius), ray);  // zero length: b = 0, miss
}

}  // namespace

namespace detail {

LocalHit ray_rounded_outline(const OutlineView& o, float radius, Vec2 p, Vec2 d,
                             bool& inside) noexcept {
  const float r = radius;
  const Clip clip = clip_ray_outline(o, p, d, r);
  inside = clip.inside;
  // Rounded outline: the union of the core, each edge swept outward by r and a disc of radius r
  // at each vertex. It lies inside the outline of edges pushed out by r, and differs from it
  // only in the corner kites beyond each vertex, which are bounded towards the shape by that
  // vertex's disc. So: the entry into the pushed-out outline is the answer when it lands
  // beside its edge; when it lands in a kite, only that vertex's disc can be hit.
  if (clip.plane < 0) return {};  // a miss, or the origin is already in the pushed-out outline
  const Vec2 entry = p + clip.fraction * d;
  // The entry lies on the entering edge's pushed line: beside the edge (its band), or beyond
  // one of its ends. At a corner where the outline turns, beyond the end means in the corner's
  // kite, before the next edge's band (exactly: a valid entry is within r tan(a/2) of the
  // corner's foot, a the turn), and only the corner's disc can be hit. Where the outline runs
  // straight on (collinear edges: an upright capsule's segment beside a box's side in B - S;
  // or nearly, where the clip's choice between equal pushed lines is rounding) the entry can
  // lie in a later edge's band, or beyond it too: walk along until the band or the kite.
  const auto next = [&o](int k) { return next_vertex(k, o.count); };
  int i = clip.plane;
  for (int step = 0; step < o.count; ++step) {
    const Vec2 v0 = o.vertices[i];
    const Vec2 e = o.vertices[next(i)] - v0;
    const float s = dot(entry - v0, e);
    const float ee = length_squared(e);
    if (s >= 0.0f && s <= ee) return {true, clip.fraction, o.normals[i]};
    const bool forwards = s > ee;
    const int j = forwards ? next(i) : previous_vertex(i, o.count);
    const Vec2 w0 = o.vertices[j];
    const Vec2 f = o.vertices[next(j)] - w0;
    const float sj = dot(entry - w0, f);
    // Before the next edge's start (going forwards) or past the previous edge's end (going
    // backwards): the kite of the corner between i and j.
    if (forwards ? sj < 0.0f : sj > length_squared(f)) {
      return ray_disc(p - (forwards ? o.vertices[next(i)] : v0), d, r);
    }
    i = j;
  }
  return {};  // only for a degenerate outline (every edge collinear)
}

RoundedPolygonEntry ray_rounded_polygon(const Polygon& poly, float radius, Vec2 p,
                                        Vec2 d) noexcept {
  bool inside = false;
  const LocalHit hit = ray_rounded_outline({poly.vertices.data(), poly.normals.data(), poly.count},
                                           radius, p, d, inside);
  if (!inside) return {hit};
  // The origin is in the pushed-out polygon. In a kite outside the rounded shape the ray can
  // still hit that kite's vertex disc.
  const PointQuery q = closest_point(poly, Transform{}, p);  // signed, to poly's own radius
  const float gap = q.distance + poly.radius - radius;       // to the core grown by radius
  if (!(gap > 0.0f) || q.feature.type != FeatureType::vertex) return {{}, gap};
  return {ray_disc(p - poly.vertices[q.feature.index], d, radius), gap};
}

}  // namespace detail

template <Shape2DType S>
RayHit raycast(const S& shape, const Transform& xf, const Ray& ray) noexcept {
  return raycast_placed(shape, xf, ray);
}

template RayHit raycast(const Circle&, const Transform&, const Ray&) noexcept;
template RayHit raycast(const Capsule&, const Transform&, const Ray&) noexcept;
template RayHit raycast(const Polygon&, const Transform&, const Ray&) noexcept;
template RayHit raycast(const Segment&, const Transform&, const Ray&) noexcept;

RayHit raycast(const Shape2D& shape, const Transform& xf, const Ray& ray) noexcept {
  return std::visit([&](const auto& s) { return raycast(s, xf, ray); }, shape);
}

}  // namespace collide
