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
#include <collide/core/lanes.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/closest_point.hpp>

#include "clip_ray.hpp"
#include "ray_ball.hpp"
#include "rounded_polygon_ray.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

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

/// Capsule: the union of three convex pieces, the band |y| <= r over 0 <= x <= L along its axis
/// (x from a towards b, y to the left) and the discs of radius r at a and b. A ray from outside
/// enters a union where it first enters a piece, so the cast is the earliest of three entries,
/// worked out side by side in SSE lanes (collide/core/lanes.hpp): lane 0 the flat side facing
/// the origin (crossed beside the core: 0 <= x <= L there), lanes 1 and 2 the discs (ray_ball's
/// entry); an origin in any piece is inside the capsule, no hit (the band is entered through its
/// ends only inside a disc, so those need no test). Ericson, Real-Time Collision Detection,
/// 5.3.7, in 2D. The axis coordinates are kept scaled by L (dot and cross products with b - a),
/// one division serves the side (1 / -dy), the discs (1 / |d|^2) and the side's normal (1 / L),
/// and hit or miss and the piece hit are masks and a lane index, not branches: random rays take
/// each case at random (the one branch: a ray clear of the strip |y| <= r is a miss before the
/// lanes, below). The capsule is cast in a frame turned as the world and centred on its
/// placement, as in 3D (raycast3.cpp): its ends are rotated (two rotations) instead of the ray
/// into its frame and the normal back out (three); (origin - p) first, so that large coordinates
/// cancel. bench_ray_cast, capsules visited in an unlearnable order, AMD EPYC: 41 -> 33 ns a cast
/// for the turned frame (stop 54); 32.9-36.4 -> 28.5-29.5 ns for the lanes (before, the disc was
/// chosen by the side's x and the cases by bit-mask selects on scalars, each float moved through
/// an integer register and back: 300 instructions). GCC's register allocation of this function
/// is touchy: a sqrt in lanes for L, or the point masked in lanes, measured 33-45 ns.
template <bool kRound>
COLLIDE_ALWAYS_INLINE RayHit capsule_cast(const Capsule& capsule, const Transform& xf, const Ray& ray) noexcept {
  using namespace simd;
  const Vec2 a = rotate(xf.q, capsule.a);
  const Vec2 axis = rotate(xf.q, capsule.b) - a;
  const Vec2 rel = (ray.origin - xf.p) - a;
  const float r = capsule.radius;
  const Vec2 d = ray.translation;
  // Lanes: 0 the flat side facing the origin, 1 the disc at a, 2 the disc at b, 3 spare.
  const LaneMask side_lane = masks(true, false, false, false);
  const LaneMask disc_lanes = masks(false, true, true, false);
  const Lanes zero = splat(0.0f), one = splat(1.0f);
  // Scalars first: the origin and the ray across and along the axis, scaled by L.
  const float ll_s = length_squared(axis);
  const float length_s = std::sqrt(ll_s);
  const float px_s = dot(rel, axis), py_s = cross(axis, rel);
  const float dpx_s = dot(d, axis), dpy_s = cross(axis, d);
  const float rl_s = r * length_s;
  {
    // Early out: a ray that stays on one side of the strip |y| <= r about the core's line,
    // which holds the capsule, misses (its ends' y, scaled by L as py_s). Only clear misses,
    // beyond kCapsuleMissSlack: a grazing ray goes on to the lanes. Misses are most random
    // rays, and one taken here skips the lanes. (A test along the axis as well, beyond the
    // ends, measured no faster.)
    const float y_lo = std::min(py_s, py_s + dpy_s), y_hi = std::max(py_s, py_s + dpy_s);
    const float reach = (1.0f + detail::kCapsuleMissSlack) * rl_s;
    if ((y_lo > reach) | (y_hi < -reach)) return {};
  }
  // One division for three: the side's 1 / -dy (lane 0), the discs' 1 / |d|^2, 1 / L (lane 3).
  const float dd_s = length_squared(d);
  const Lanes inv = one / lanes(-dpy_s, dd_s, dd_s, length_s);
  const Lanes inv_dd = splat(inv[1]);
  // The discs: the origin relative to each end.
  const Lanes dx = splat(d.x), dy = splat(d.y), rr = splat(r);
  const Lanes mx = lanes(0.0f, rel.x, rel.x - axis.x, 0.0f), my = lanes(0.0f, rel.y, rel.y - axis.y, 0.0f);
  const Lanes b = mx * dx + my * dy;
  const Lanes c = mx * mx + my * my - rr * rr;
  const Lanes tc = -b * inv_dd;
  const Lanes cx = mx + tc * dx, cy = my + tc * dy;
  const Lanes disc = rr * rr - (cx * cx + cy * cy);
  const Lanes t_disc = simd::max(tc - simd::sqrt(simd::max(disc, zero) * inv_dd), zero);
  const LaneMask disc_ok = disc_lanes & (c > zero) & (b < zero) & (disc >= zero) & (t_disc <= one);
  // The side.
  const Lanes py = splat(py_s), rl = splat(rl_s), px = splat(px_s), ll = splat(ll_s), dpy = splat(dpy_s);
  const LaneMask above = (py > rl) | (py < -rl);
  const Lanes side = select(py > zero, one, -one);
  const Lanes t_side = (py - side * rl) * inv;
  const Lanes x_side = px + t_side * splat(dpx_s);
  const LaneMask side_ok = above & (side * dpy < zero) & (t_side <= one) & (x_side >= zero) & (x_side <= ll);
  const LaneMask ok = (side_ok & side_lane) | disc_ok;
  const Lanes t = select(side_lane, t_side, t_disc);
  // A crossing of the side beside the core is the answer (the capsule lies inside the strip
  // |y| <= r, so nothing of it is entered earlier): ranked first, so that a disc's entry within
  // rounding of it cannot name the disc, whose normal is turned there.
  const Lanes rank = select(side_lane, -one, t);
  const Lanes first = horizontal_min(select(ok, rank, splat(std::numeric_limits<float>::infinity())));
  // An origin in the band between the ends or in a disc is inside: no hit.
  const LaneMask inside = (~above & (px >= zero) & (px <= ll) & side_lane) | (disc_lanes & (c <= zero));
  const LaneMask keep = (first <= one) & (horizontal_min(select(inside, -one, zero)) >= zero);
  const bool hit = lane_bits(keep) & 1u;
  // The piece hit (the first of equal entries), or slot 4, which holds a miss's zeros.
  const int k = std::countr_zero(lane_bits(ok & (rank == first) & keep) | 16u);
  // Normals: the side's across the axis, a disc's from its centre (facing the ray for r = 0).
  alignas(16) float fractions[5], normal_x[5], normal_y[5];
  store(fractions, t);
  const Lanes face = -simd::sqrt(inv_dd);
  if constexpr (kRound) {
    // Made unit, not divided by r (a ray from far away rounds the offset by more than r's
    // precision); an offset with no direction (dead on within rounding) faces the ray, as
    // ray_ball.
    const Lanes ox = mx + t * dx, oy = my + t * dy;
    const Lanes oo = ox * ox + oy * oy;
    const Lanes scale = one / simd::sqrt(oo);
    const LaneMask towards_centre = oo >= splat(kMinDirectionLengthSquared);
    store(normal_x, select(towards_centre, ox * scale, dx * face));
    store(normal_y, select(towards_centre, oy * scale, dy * face));
  } else {
    store(normal_x, dx * face);
    store(normal_y, dy * face);
  }
  const float side_scale = side[0] * inv[3];
  normal_x[0] = -axis.y * side_scale;
  normal_y[0] = axis.x * side_scale;
  fractions[4] = normal_x[4] = normal_y[4] = 0.0f;
  const float fraction = fractions[k];
  const std::uint32_t hit_mask = detail::mask_of(hit);
  const Vec2 point = ray.at(fraction);
  return {hit, fraction, {detail::keep_if(point.x, hit_mask), detail::keep_if(point.y, hit_mask)},
          {normal_x[k], normal_y[k]}};
}

RayHit raycast_placed(const Capsule& capsule, const Transform& xf, const Ray& ray) noexcept {
  if (!(length_squared(ray.translation) > 0.0f)) return {};
  // A radius too small to give directions (detail::is_round) is a segment here, as in 3D.
  return detail::is_round(capsule.radius) ? capsule_cast<true>(capsule, xf, ray)
                                          : capsule_cast<false>(capsule, xf, ray);
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

// raycast_placed flattened into each: the point and normal it would build are dead code, and the
// hit and fraction are made by the same instructions as raycast's (this file is compiled
// without fused multiply-adds, so no contraction can round one form differently).
template <Shape2DType S>
COLLIDE_FLATTEN RayFraction raycast_fraction(const S& shape, const Transform& xf, const Ray& ray) noexcept {
  const RayHit h = raycast_placed(shape, xf, ray);
  return {h.hit, h.fraction};
}

template RayFraction raycast_fraction(const Circle&, const Transform&, const Ray&) noexcept;
template RayFraction raycast_fraction(const Capsule&, const Transform&, const Ray&) noexcept;
template RayFraction raycast_fraction(const Polygon&, const Transform&, const Ray&) noexcept;
template RayFraction raycast_fraction(const Segment&, const Transform&, const Ray&) noexcept;

RayFraction raycast_fraction(const Shape2D& shape, const Transform& xf, const Ray& ray) noexcept {
  return std::visit([&](const auto& s) { return raycast_fraction(s, xf, ray); }, shape);
}

}  // namespace collide
