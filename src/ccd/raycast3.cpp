// Ray casts against single 3D shapes, under the rules of the 2D ones (raycast.cpp): the ray is
// moved into the shape's local frame first (subtract the position, then undo the rotation), all
// work is local, the normal is rotated back once; the ray must *enter* the shape, so an origin
// in the closed shape reports no hit, and so does a ray of zero length or with a NaN coordinate.

#include <collide/ccd/raycast.hpp>

#include <collide/core/config.hpp>
#include <collide/core/lanes.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/closest_point.hpp>

#include "clip_ray.hpp"
#include "ray_ball.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace collide {
namespace {

using LocalHit3 = detail::LocalHitN<3>;

/// The local ray: origin and translation in the shape's frame.
struct LocalRay3 {
  Vec3 origin;
  Vec3 translation;
};

/// The ray in the frame `f` (the placement's matrix form: its rotation made once, then three
/// dot products a vector, where a quaternion rotates each vector by two cross products).
LocalRay3 to_local(const Frame3& f, const Ray3& ray) noexcept {
  return {inv_transform_point(f, ray.origin), inv_rotate(f, ray.translation)};
}

/// The hit of `h` on `ray` with the world-space normal `normal`. Without a branch on whether it
/// hit (random rays hit or miss at random): a miss's fields are zero (its point masked).
RayHit3 world_hit(const LocalHit3& h, const Ray3& ray, Vec3 normal) noexcept {
  const std::uint32_t keep = detail::mask_of(h.hit);
  const Vec3 at = ray.at(h.fraction);
  RayHit3 out;
  out.hit = h.hit;
  out.fraction = h.fraction;
  out.point = {detail::keep_if(at.x, keep), detail::keep_if(at.y, keep),
               detail::keep_if(at.z, keep)};
  out.normal = normal;
  return out;
}

/// The world-space hit of a hit in the frame `f`.
RayHit3 to_world(const LocalHit3& h, const Frame3& f, const Ray3& ray) noexcept {
  return world_hit(h, ray, rotate(f, h.normal));
}

/// Capsule: every point within r of the core a-b, the union of three convex pieces: the stretch
/// 0 <= x <= L of the infinite cylinder of radius r about the core's line (x along the axis from
/// a towards b) and the balls of radius r at a and b. A ray from outside enters a union where it
/// first enters a piece, so the cast is the earliest of three entries, worked out side by side
/// in SSE lanes (collide/core/lanes.hpp) with one formula, ray_ball's entry: lanes 1 and 2 the
/// balls; lane 0 the cylinder, whose entry is the entry of the ray's projection across the axis
/// into the disc of radius r (the same closest-approach discriminant, Haines et al., Ray Tracing
/// Gems 7), kept when it lands beside the core (0 <= x <= L). An origin in any piece is inside
/// the capsule: no hit. (The cylinder's stretch is entered through its end discs only inside a
/// ball, so those need no test.) Ericson, Real-Time Collision Detection, 5.3.7. Across the axis
/// the vectors are crossed with it (m x axis: turned a right angle about the axis and scaled by
/// L, the disc's radius r L), so no division comes before the lanes' one, which serves all
/// three; the lanes' squares grow as L^2 |m|^2, within float range for capsules and rays up to
/// about 1e9 long (the early out's as L^4 |m|^2 |d|^2: where those overflow, beyond about 5e4,
/// the ray goes on to the lanes). The piece hit is a lane index (a miss reads lane 0, masked at
/// the end): no branch on the data (random rays take each case at random) but one: a line that
/// passes clear of the cylinder is a miss before the lanes (below). `kNormal` false gives the hit and
/// fraction alone: the same value, taken from the lanes by a shorter chain than the piece's
/// index (stop 80, below). Normals are normalised rather than divided by r: a ray from far away
/// (relative to r) rounds the offset by more than r's float precision. A zero radius is a
/// segment, grazed dead on: face the ray (across the axis on the cylinder); so does an offset too
/// small to give a direction (below kMinDirectionLengthSquared: a radius of 1e-20 hit dead on made
/// the normal NaN, fuzz_shapes).
/// An entry beside the core outranks the balls' (below). bench_ray_cast3, AMD EPYC, the builds
/// alternating: 52-62 -> 37-39 ns a cast, Jolt 62-65 (the cases by branches before: about 0.9
/// mispredictions and 350 instructions a cast). Stop 80 (the vectors across the axis by cross
/// products, which the early out needs without the dot products m_perp = m L^2 - (m . axis)
/// axis waited for; the fraction alone by selects; then every step in lanes, the scalar form
/// having spilled registers): the fraction alone 38.4 -> 30.3-32.2 ns, the full cast 41.9-42.8
/// -> 39.7-42.2 (interleaved runs, builds alternating, the host's fast phase; Jolt 63-65 /
/// 78-81). Stop 84 (the normal of the piece hit alone, in scalars, where every lane's was
/// normalised): the full cast 29.7 -> 28.1 ns, the fraction alone 22.4, Jolt with its normal
/// 57.9 (AMD EPYC Zen 5, interleaved, builds alternating; bringing the piece's offset to lane 0
/// by selects instead of a store and an indexed load measured 29.9).
///
/// `ends_x`, `ends_y`, `ends_z`: lanes 0 and 1 the ends a and b in the ray's frame (as the placed
/// cast turns them); `p` the ray's origin relative to that frame's origin, `d` its translation.
template <bool kRound, bool kNormal>
COLLIDE_ALWAYS_INLINE LocalHit3 capsule_cast(simd::Lanes ends_x, simd::Lanes ends_y, simd::Lanes ends_z, float r,
                                             Vec3 p, Vec3 d) noexcept {
  using namespace simd;
  // Every step is done in lanes, the cylinder's in lane 0 beside the balls' (the scalar form
  // kept more vectors live than SSE has registers: they went to the stack and back).
  // The axis b - a in every lane.
  const Lanes ax = broadcast<1>(ends_x) - broadcast<0>(ends_x), ay = broadcast<1>(ends_y) - broadcast<0>(ends_y),
              az = broadcast<1>(ends_z) - broadcast<0>(ends_z);
  // Lanes: 0 the cylinder, 1 the ball at a, 2 the ball at b, 3 spare. Each ball's origin is
  // p - its centre, one rounding (m - axis rounds three times: rays from 1e4 radii away turned
  // the normal by twice its tolerance); lane 0 starts as the ball at a's.
  const Lanes px = splat(p.x) - shuffle<0, 0, 1, 1>(ends_x),
              py = splat(p.y) - shuffle<0, 0, 1, 1>(ends_y),
              pz = splat(p.z) - shuffle<0, 0, 1, 1>(ends_z);
  const Lanes dx = splat(d.x), dy = splat(d.y), dz = splat(d.z);
  // Across the axis (lane 0): the origin and the translation crossed with it, turned a right
  // angle about the axis and scaled by L, so the cylinder is the disc of radius r L there.
  const Lanes mx = with_lane0(px, py * az - pz * ay), my = with_lane0(py, pz * ax - px * az),
              mz = with_lane0(pz, px * ay - py * ax);
  const Lanes ux = with_lane0(dx, dy * az - dz * ay), uy = with_lane0(dy, dz * ax - dx * az),
              uz = with_lane0(dz, dx * ay - dy * ax);
  const Lanes ll = ax * ax + ay * ay + az * az;  // x coordinates below are scaled by L^2
  const float rr_ll = (r * r) * ll[0];
  const Lanes dd = ux * ux + uy * uy + uz * uz;
  if constexpr (kRound) {
    // Early out: a ray whose line passes farther than r from the core's line misses the
    // cylinder about it, which holds the capsule (line to line distance |m' x d'| / |d'| across
    // the axis, here squared and scaled by L as m' and d' are: no division; at most the origin's
    // distance from the axis, so a ray along the axis, whose d' is rounding, cannot leave here
    // wrongly). Only clear misses, beyond kCapsuleMissSlack: a grazing line goes on to the lanes,
    // whose rounding decides as before. Misses are most random rays (52% of bench_ray_cast3's
    // leave here), and one taken here skips the lanes. (Overflowing squares, at the range's far
    // end, go on to the lanes too.)
    const Lanes wx = my * uz - mz * uy, wy = mz * ux - mx * uz, wz = mx * uy - my * ux;
    const float apart = (wx * wx + wy * wy + wz * wz)[0];
    if (apart < std::numeric_limits<float>::infinity() &&
        apart > (1.0f + detail::kCapsuleMissSlack) * rr_ll * dd[0]) {
      return {};
    }
  }
  const Lanes zero = splat(0.0f), one = splat(1.0f);
  const Lanes rr = with_lane0(splat(r * r), splat(rr_ll));
  const Lanes b = mx * ux + my * uy + mz * uz;
  const Lanes c = mx * mx + my * my + mz * mz - rr;
  const Lanes inv = one / dd;
  const Lanes tc = -b * inv;
  const Lanes cx = mx + tc * ux, cy = my + tc * uy, cz = mz + tc * uz;
  const Lanes disc = rr - (cx * cx + cy * cy + cz * cz);
  const Lanes t = tc - simd::sqrt(simd::max(disc, zero) * inv);
  // Along the axis (lane 0; the balls' lanes read 0, which is within [0, L^2]).
  const Lanes x0 = with_lane0(zero, px * ax + py * ay + pz * az);
  const Lanes x_rate = with_lane0(zero, dx * ax + dy * ay + dz * az);
  const Lanes top = ll;
  const Lanes x = x0 + t * x_rate;
  const LaneMask used = masks(true, true, true, false);
  const LaneMask ok = used & (c > zero) & (b < zero) & (disc >= zero) & (t <= one) & (x >= zero) & (x <= top);
  // An entry beside the core is the answer (the capsule lies inside the cylinder, so nothing of
  // it is entered earlier): ranked first. The balls' entries are within rounding of it there,
  // and the earliest of those alone could name a ball, whose normal is turned by up to
  // sqrt(2 (L - x) / r) (rays from 1e4 radii away: 0.03 rad).
  // An origin in the cylinder's stretch or in a ball is inside: no hit.
  const LaneMask inside = used & (c <= zero) & (x0 >= zero) & (x0 <= top);
  const Lanes inf = splat(std::numeric_limits<float>::infinity());
  if constexpr (!kNormal) {
    // The fraction alone: lane 0's entry where that is one, else the earlier of the balls' (the
    // value the piece's index below picks, by a shorter chain of selects).
    const bool hit = (lane_bits(ok) != 0u) & (lane_bits(inside) == 0u);
    const Lanes entries = select(ok, t, inf);
    const Lanes balls = simd::min(broadcast<1>(entries), broadcast<2>(entries));
    const float fraction = simd::max(select(ok, entries, balls), zero)[0];
    return {hit, detail::keep_if(fraction, detail::mask_of(hit)), Vec3{0.0f}};
  } else {
    const Lanes rank = select(masks(true, false, false, false), -one, t);
    const Lanes first = horizontal_min(select(ok, rank, inf));
    const LaneMask keep = (first <= one) & (horizontal_min(select(inside, -one, zero)) >= zero);
    // The piece hit (the first of equal entries); a miss reads lane 0 and is masked at the end.
    const unsigned hits = lane_bits(ok & (rank == first) & keep);
    const bool hit = hits != 0u;
    const int k = std::countr_zero(hits | 16u) & 3;
    // The normal for that piece alone, in scalars: the entry's offset from the piece, (p - c) +
    // t d with c the ball's centre or, on the cylinder, less its part along the axis (x / L^2 of
    // the axis; the balls' lanes read x = 0), for every lane in three stores; the piece's
    // normalisation alone is then one square root (the lanes' form, every piece's offset turned
    // back from across the axis and normalised, measured 13 ns over the fraction alone).
    const float inv_ll = 1.0f / ll[0];
    const Lanes along = x * splat(inv_ll);
    alignas(16) float fraction[4], ox[4], oy[4], oz[4];
    store(fraction, simd::max(t, zero));
    store(ox, px + t * dx - along * ax), store(oy, py + t * dy - along * ay), store(oz, pz + t * dz - along * az);
    Vec3 o{ox[k], oy[k], oz[k]};
    float oo = dot(o, o);
    if (!kRound || (hit & !(oo >= kMinDirectionLengthSquared))) [[unlikely]] {
      // An offset with no direction (the ray dead on within rounding of the axis or a centre;
      // every offset of a capsule too thin to be round) faces the ray, as ray_ball: the
      // translation, less its part along the axis on the cylinder.
      const float rate = k == 0 ? x_rate[0] * inv_ll : 0.0f;
      o = -(d - rate * Vec3{ax[0], ay[0], az[0]});
      oo = dot(o, o);
    }
    const Vec3 n = o * (1.0f / std::sqrt(oo));
    const std::uint32_t mask = detail::mask_of(hit);
    return {hit, detail::keep_if(fraction[k], mask),
            {detail::keep_if(n.x, mask), detail::keep_if(n.y, mask), detail::keep_if(n.z, mask)}};
  }
}

/// The capsule's ends as capsule_cast takes them: a in lane 0, b in lane 1.
struct EndLanes {
  simd::Lanes x, y, z;
};
EndLanes end_lanes(const Capsule3& capsule) noexcept {
  const Vec3 a = capsule.a, b = capsule.b;
  return {simd::lanes(a.x, b.x, 0.0f, 0.0f), simd::lanes(a.y, b.y, 0.0f, 0.0f), simd::lanes(a.z, b.z, 0.0f, 0.0f)};
}

/// A radius too small to give directions (detail::is_round: r below about 1e-19) is a segment
/// here: a ball's hit offset would be too small to normalise.
LocalHit3 raycast_local(const Capsule3& capsule, Vec3 p, Vec3 d) noexcept {
  const EndLanes e = end_lanes(capsule);
  return detail::is_round(capsule.radius) ? capsule_cast<true, true>(e.x, e.y, e.z, capsule.radius, p, d)
                                          : capsule_cast<false, true>(e.x, e.y, e.z, capsule.radius, p, d);
}

/// Segment: see the header for the rule. The ray p + t d and the segment a + s e: in general
/// position their lines are skew, at distance |r . (d x e)| / |d x e| (r = p - a); the ray hits
/// when that is within the tolerance and the closest points of the two lines fall within
/// t in (0, 1] and s in [0, 1].
LocalHit3 raycast_local(const Segment3& seg, Vec3 p, Vec3 d) noexcept {
  const Vec3 e = seg.b - seg.a;
  const Vec3 r = p - seg.a;
  const float ee = length_squared(e);
  const float dd = length_squared(d);
  if (!(dd > 0.0f)) return {};
  const float tol2 = kRelativeTolerance * kRelativeTolerance * (ee + dd);
  const Vec3 n = cross(d, e);
  const float nn = length_squared(n);
  if (nn <= kParallelTolerance * kParallelTolerance * ee * dd) {
    // Parallel: the distance of the origin from the segment's line decides.
    if (!(length_squared(cross(r, e)) <= tol2 * ee)) return {};
    const float s0 = dot(r, e) / ee;  // origin and rate along the segment, in segment lengths
    const float ds = dot(d, e) / ee;
    const Vec3 u = e * (1.0f / std::sqrt(ee));
    if (s0 < 0.0f && ds > 0.0f && -s0 <= ds) return {true, -s0 / ds, -u};
    if (s0 > 1.0f && ds < 0.0f && s0 - 1.0f <= -ds) return {true, (s0 - 1.0f) / -ds, u};
    return {};  // heading away, too short, or starting on the segment
  }
  const float gap = dot(r, n);  // |d x e| times the distance between the lines
  if (!(gap * gap <= tol2 * nn)) return {};
  // Closest points of the two lines (the minimum of |r + t d - s e|^2, by Cramer's rule written
  // with cross products): t = ((e x r) . n) / |n|^2, s = ((d x r) . n) / |n|^2.
  const float t = dot(cross(e, r), n) / nn;
  const float s = dot(cross(d, r), n) / nn;
  // An origin within the tolerance of the crossing is on the segment: no entry.
  if (!(t > 0.0f && t * t * dd > tol2 && t <= 1.0f && s >= 0.0f && s <= 1.0f)) return {};
  // Across the segment in the common plane, facing the origin: -(d without its e component).
  const Vec3 across = d - (dot(d, e) / ee) * e;
  return {true, t, -across * (1.0f / length(across))};
}

/// Box (no radius): the slab test (Kay & Kajiya 1986; Williams et al., JGT 2005). On axis k
/// the ray is between the box's faces for t between (-h - p) / d and (h - p) / d; the entry is
/// the largest lower bound (its axis names the face; the first axis on a tie), the box is
/// missed if it exceeds the smallest upper bound. The lower bound starts at 0 and is raised
/// only by an entry strictly after the origin, so an origin in the closed box (entries <= 0)
/// reports no hit. A ray parallel to a slab (d = 0 there) is outside for good unless the origin
/// is within it. With SSE2 the three axes go in lanes and the miss is a mask, without branches
/// (random rays decide which axis enters and whether the box is hit at random: 40 -> 25 ns a
/// cast, bench_ray_cast3, AMD EPYC).
LocalHit3 slab_cast(Vec3 half, Vec3 p, Vec3 d) noexcept {
#if defined(__SSE2__) || defined(_M_X64)
  // Lane 3 is a slab of half width 0 around 0 that the ray runs along: it never decides.
  const __m128 h = _mm_setr_ps(half.x, half.y, half.z, 0.0f);
  const __m128 vp = _mm_setr_ps(p.x, p.y, p.z, 0.0f);
  const __m128 vd = _mm_setr_ps(d.x, d.y, d.z, 0.0f);
  const __m128 sign_bit = _mm_set1_ps(-0.0f);
  const __m128 infinity = _mm_set1_ps(std::numeric_limits<float>::infinity());
  // The face the ray meets first on each axis, -copysign(h, d), and the other, copysign(h, d).
  const __m128 near_face = _mm_or_ps(h, _mm_and_ps(sign_bit, _mm_xor_ps(vd, sign_bit)));
  const __m128 far_face = _mm_xor_ps(near_face, sign_bit);
  const __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), vd);
  const __m128 parallel = _mm_cmpeq_ps(vd, _mm_setzero_ps());
  __m128 t_near = _mm_mul_ps(_mm_sub_ps(near_face, vp), inv);
  __m128 t_far = _mm_mul_ps(_mm_sub_ps(far_face, vp), inv);
  // Parallel: outside the slab (or NaN) misses; else no bound. Otherwise a NaN bound misses.
  const __m128 out_of_slab = _mm_cmpnle_ps(_mm_andnot_ps(sign_bit, vp), h);
  const __m128 miss = _mm_or_ps(_mm_and_ps(parallel, out_of_slab),
                                _mm_andnot_ps(parallel, _mm_cmpnle_ps(t_near, t_far)));
  const __m128 minus_infinity = _mm_xor_ps(infinity, sign_bit);
  t_near = _mm_or_ps(_mm_and_ps(parallel, minus_infinity), _mm_andnot_ps(parallel, t_near));
  t_far = _mm_or_ps(_mm_and_ps(parallel, infinity), _mm_andnot_ps(parallel, t_far));
  __m128 entry = _mm_max_ps(t_near, _mm_shuffle_ps(t_near, t_near, _MM_SHUFFLE(1, 0, 3, 2)));
  entry = _mm_max_ps(entry, _mm_shuffle_ps(entry, entry, _MM_SHUFFLE(2, 3, 0, 1)));
  __m128 exit = _mm_min_ps(t_far, _mm_shuffle_ps(t_far, t_far, _MM_SHUFFLE(1, 0, 3, 2)));
  exit = _mm_min_ps(exit, _mm_shuffle_ps(exit, exit, _MM_SHUFFLE(2, 3, 0, 1)));
  const float t_in = _mm_cvtss_f32(entry);
  const float t_out = std::min(_mm_cvtss_f32(exit), 1.0f);
  const bool hit = (_mm_movemask_ps(miss) == 0) & (t_in > 0.0f) & (t_in <= t_out);
  // The first axis holding the entry (lane 3 never does: its bound is -inf).
  const auto holds = static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(t_near, entry)));
  const int axis = std::countr_zero(holds | 8u) & 3;
  const float direction[4] = {d.x, d.y, d.z, 1.0f};
  float n[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  n[axis] = -std::copysign(1.0f, direction[axis]);  // against the ray
  const std::uint32_t keep = detail::mask_of(hit);
  return {hit, detail::keep_if(t_in, keep),
          Vec3{detail::keep_if(n[0], keep), detail::keep_if(n[1], keep),
               detail::keep_if(n[2], keep)}};
#else
  float t_in = 0.0f;
  float t_out = 1.0f;
  int axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0f) {
      if (!(std::fabs(p[k]) <= half[k])) return {};  // parallel and outside the slab (or NaN)
      continue;
    }
    const float inv = 1.0f / d[k];
    const float t_near = (-std::copysign(half[k], d[k]) - p[k]) * inv;
    const float t_far = (std::copysign(half[k], d[k]) - p[k]) * inv;
    if (!(t_near <= t_far)) return {};  // NaN
    if (t_near > t_in) {
      t_in = t_near;
      axis = k;
    }
    t_out = std::min(t_out, t_far);
  }
  if (axis < 0 || t_in > t_out) return {};
  Vec3 n(0.0f);
  n[axis] = d[axis] > 0.0f ? -1.0f : 1.0f;
  return {true, t_in, n};
#endif
}

/// The first fraction in [t0, t1] at which the ray is within r of the core feature that is
/// closest to it throughout that stretch, given by the axes the ray is outside of (side[k] =
/// -1, +1, or 0 when within the half extent: a face for one outside axis, an edge for two, a
/// corner for three). The offset from the feature is v(t) = m + t d on the outside axes (m =
/// p - side * half there, 0 on the others), so the first fraction with |v| <= r is the smaller
/// root of |m + t d|^2 = r^2, taken from the closest approach as in ray_ball (Haines et al.).
/// Returns a negative fraction when the stretch stays farther than r.
struct RegionEntry {
  float fraction = -1.0f;
  Vec3 normal{0.0f};
};

RegionEntry region_entry(Vec3 half, float r, Vec3 p, Vec3 d, float t0, float t1,
                         const std::array<int, 3>& side) noexcept {
  Vec3 m(0.0f), dm(0.0f);
  for (int k = 0; k < 3; ++k) {
    if (side[k] != 0) {
      m[k] = p[k] - static_cast<float>(side[k]) * half[k];
      dm[k] = d[k];
    }
  }
  const Vec3 v0 = m + t0 * dm;
  if (length_squared(v0) <= r * r) {
    // Already within r at the start of the stretch (the core itself when no axis is outside).
    const Vec3 n = normalize_or_zero(v0);
    return {t0, n};
  }
  const float b = dot(v0, dm);  // rate of change of |v|^2 / 2 at t0
  if (!(b < 0.0f)) return {};   // moving away from the feature: |v| only grows (convex)
  const float inv_aa = 1.0f / length_squared(dm);
  const float tc = -b * inv_aa;  // closest approach, relative to t0
  const Vec3 closest = v0 + tc * dm;
  const float disc = r * r - length_squared(closest);
  if (disc < 0.0f) return {};
  const float t = t0 + std::max(tc - std::sqrt(disc * inv_aa), 0.0f);
  if (!(t <= t1)) return {};
  return {t, normalize_or_zero(m + t * dm)};
}

/// Rounded box: every point within r of the core box [-h, h]. It lies inside the box grown by
/// r (E), and differs from E only near E's edges and corners. Clip the ray by E's slabs: if it
/// enters E at a point whose other two coordinates are within the core's half extents, that
/// point is on the rounded box's flat face. Otherwise (or when the origin is inside E) follow
/// the ray from there until it leaves E: a coordinate crosses a half extent at most twice, so
/// at most 6 fractions cut the ray into stretches over each of which one core feature (face,
/// edge or corner) is closest; region_entry solves each in order. The distance to the core
/// is convex along the ray, so the first stretch that reaches r holds the entry. Exact up to
/// rounding, with no approximation of the rounded edges and corners.
LocalHit3 rounded_box_cast(Vec3 half, float r, Vec3 p, Vec3 d) noexcept {
  const Vec3 grown = half + Vec3(r);
  float t_in = 0.0f;
  float t_out = 1.0f;
  int axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0f) {
      if (!(std::fabs(p[k]) <= grown[k])) return {};
      continue;
    }
    const float inv = 1.0f / d[k];
    const float t_near = (-std::copysign(grown[k], d[k]) - p[k]) * inv;
    const float t_far = (std::copysign(grown[k], d[k]) - p[k]) * inv;
    if (!(t_near <= t_far)) return {};
    if (t_near > t_in) {
      t_in = t_near;
      axis = k;
    }
    t_out = std::min(t_out, t_far);
  }
  if (t_in > t_out) return {};
  if (axis >= 0) {
    const Vec3 q = p + t_in * d;
    const int j = (axis + 1) % 3;
    const int k = (axis + 2) % 3;
    if (std::fabs(q[j]) <= half[j] && std::fabs(q[k]) <= half[k]) {
      Vec3 n(0.0f);
      n[axis] = d[axis] > 0.0f ? -1.0f : 1.0f;
      return {true, t_in, n};
    }
  }
  // The fractions in (t_in, t_out) where a coordinate crosses a half extent, in order.
  std::array<float, 8> cuts{};
  int count = 0;
  cuts[count++] = t_in;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0f) continue;
    for (const float h : {-half[k], half[k]}) {
      const float t = (h - p[k]) / d[k];
      if (!(t > t_in && t < t_out)) continue;
      int i = count++;  // insertion: at most 6 cuts
      for (; cuts[i - 1] > t; --i) cuts[i] = cuts[i - 1];
      cuts[i] = t;
    }
  }
  cuts[count++] = t_out;
  for (int i = 0; i + 1 < count; ++i) {
    const float t0 = cuts[i];
    const float t1 = cuts[i + 1];
    const Vec3 mid = p + (0.5f * (t0 + t1)) * d;  // the stretch's region, away from its ends
    std::array<int, 3> side{};
    for (int k = 0; k < 3; ++k) side[k] = mid[k] > half[k] ? 1 : (mid[k] < -half[k] ? -1 : 0);
    const RegionEntry e = region_entry(half, r, p, d, t0, t1, side);
    if (e.fraction < 0.0f) continue;
    if (!(e.fraction > 0.0f)) return {};  // the origin is in the closed rounded box
    return {true, e.fraction, e.normal};
  }
  return {};
}

LocalHit3 raycast_local(const Box& box, Vec3 p, Vec3 d) noexcept {
  if (box.radius > 0.0f) return rounded_box_cast(box.half, box.radius, p, d);
  return slab_cast(box.half, p, d);
}

/// Cyrus-Beck clipping of the ray by the hull's face planes pushed out by `offset`: four faces
/// at a time over `face_blocks` where the machine has SSE2 (rays in an order no branch
/// predictor learns, bench_ray_cast3, AMD EPYC: 111 -> 42 ns a cast on 16-point hulls, 298 -> 81
/// on 64-point ones), else one at a time.
COLLIDE_ALWAYS_INLINE detail::ClipResult clip_ray_hull(const ConvexHull& hull, Vec3 p, Vec3 d,
                                                      float offset) noexcept {
#if defined(__SSE2__) || defined(_M_X64)
  return detail::clip_ray_blocks(hull.face_blocks.data(), hull.face_blocks.size() / 16, p.x, p.y,
                                 p.z, d.x, d.y, d.z, offset);
#else
  return detail::clip_ray(static_cast<int>(hull.faces.size()), [&](int i) {
    const HullFace& f = hull.faces[i];
    return detail::PlaneCrossing{f.offset + offset - dot(f.normal, p), dot(f.normal, d)};
  });
#endif
}

/// True when `x`, on the plane of face `f`, lies within the face's polygon (closed): behind
/// the outward side of every edge, (w - v) x n for a counter-clockwise face.
bool within_face(const ConvexHull& hull, const HullFace& f, Vec3 x) noexcept {
  const HullVertexIndex* corners = hull.face_vertices.data() + f.first;
  for (int k = 0; k < f.count; ++k) {
    const Vec3 v = hull.vertices[corners[k]];
    const Vec3 w = hull.vertices[corners[k + 1 < f.count ? k + 1 : 0]];
    if (dot(cross(w - v, f.normal), x - v) > 0.0f) return false;
  }
  return true;
}

/// Rounded hull: every point within r of the core hull. It is the union of the core, one prism
/// over each face (the face swept out along its normal by r: its top is the face pushed out by
/// r) and one capsule of radius r around each edge (their end spheres are the rounded
/// corners). A ray from outside enters it first through a prism's top or a capsule (a prism's
/// sides lie inside the capsules of its edges; the core is inside the prisms). So the entry is
/// the first over the tops and the capsules, each exact (raycast_local(Capsule3)).
///
/// Fast path: the pieces all lie inside the hull with every face pushed out by r (E), so the
/// ray is first clipped by E's faces (Cyrus-Beck): no entry into E is a miss, and an entry
/// through a pushed face beside its core face (the entry minus r along the normal lies within
/// the face's polygon) is the answer, as for a rounded polygon in 2D. Otherwise (the entry is
/// near an edge or corner, or named a face whose nearly coplanar neighbour it is really beside,
/// the two being entered at fractions equal within rounding) all pieces are searched: faces
/// turned towards the ray and edges with such a face (the surface normal at an edge lies
/// between its two face normals), each capsule after a test of its bounding ball against the
/// stretch of the ray still in question. An origin inside E is first tested against the core (point
/// query): within r it is in the closed shape, no hit.
LocalHit3 rounded_hull_cast(const ConvexHull& hull, Vec3 p, Vec3 d) noexcept {
  const float r = hull.radius;
  const detail::ClipResult clip = clip_ray_hull(hull, p, d, r);
  if (clip.plane >= 0) {
    const HullFace& f = hull.faces[clip.plane];
    if (within_face(hull, f, p + clip.fraction * d - r * f.normal)) {
      return {true, clip.fraction, f.normal};
    }
  } else {
    // A miss, or the origin inside E: then it may be inside the rounded hull (or NaN).
    if (!clip.inside) return {};
    if (!(closest_point(hull, Transform3{}, p).distance > 0.0f)) return {};
  }
  LocalHit3 best;
  for (const HullFace& f : hull.faces) {
    const float den = dot(f.normal, d);
    const float num = f.offset + r - dot(f.normal, p);  // < 0: the origin is beyond the top
    if (!(den < 0.0f && num < 0.0f)) continue;
    const float t = num / den;
    if (!(t <= 1.0f) || (best.hit && t >= best.fraction)) continue;
    if (within_face(hull, f, p + t * d - r * f.normal)) best = {true, t, f.normal};
  }
  // The ray's stretch that can still hold the entry: from E's entry to the best so far.
  const float t_from = clip.plane >= 0 ? clip.fraction : 0.0f;
  const float inv_dd = 1.0f / length_squared(d);
  for (const HullEdge& e : hull.edges) {
    if (dot(hull.faces[e.face0].normal, d) >= 0.0f && dot(hull.faces[e.face1].normal, d) >= 0.0f) {
      continue;
    }
    const Vec3 a = hull.vertices[e.v0];
    const Vec3 b = hull.vertices[e.v1];
    // Cheap rejection by the capsule's bounding ball (centre the edge's middle, radius
    // |b - a| / 2 + r, squared at most 2 (|b - a|^2 / 4 + r^2)) against that stretch.
    const Vec3 centre = 0.5f * (a + b);
    const float t_to = best.hit ? best.fraction : 1.0f;
    const float t = std::clamp(dot(centre - p, d) * inv_dd, t_from, t_to);
    if (distance_squared(p + t * d, centre) > 0.5f * length_squared(b - a) + 2.0f * r * r) continue;
    const LocalHit3 h = raycast_local(Capsule3{a, b, r}, p, d);
    if (h.hit && (!best.hit || h.fraction < best.fraction)) best = h;
  }
  return best;
}

/// Hull (no radius): Cyrus-Beck clipping by its face planes; the entering face's normal.
LocalHit3 raycast_local(const ConvexHull& hull, Vec3 p, Vec3 d) noexcept {
  if (hull.radius > 0.0f) return rounded_hull_cast(hull, p, d);
  const detail::ClipResult clip = clip_ray_hull(hull, p, d, 0.0f);
  if (clip.plane < 0) return {};
  return {true, clip.fraction, hull.faces[clip.plane].normal};
}

/// Shapes with a frame: cast in the local frame, rotate the normal back.
template <class S>
RayHit3 raycast_placed(const S& shape, const Transform3& xf, const Ray3& ray) noexcept {
  const Frame3 f = Frame3::from(xf);
  const LocalRay3 local = to_local(f, ray);
  if (!(length_squared(local.translation) > 0.0f)) return {};
  return to_world(raycast_local(shape, local.origin, local.translation), f, ray);
}

/// A capsule is cast in a frame turned as the world and centred on its placement: its ends are
/// rotated there (two rotations, side by side in lanes) instead of the ray into its frame and the
/// normal back out (three), and the origin is made relative as (origin - p) so that large
/// coordinates cancel first (bench_ray_cast3, AMD EPYC: 59 -> 43 ns a cast at stop 50).
/// `kNormal` false: the hit and fraction alone (raycast_fraction's), bit for bit the full cast's.
template <bool kNormal>
RayHit3 capsule_placed(const Capsule3& capsule, const Transform3& xf, const Ray3& ray) noexcept {
  // (A zero or NaN translation needs no test of its own: no lane heads towards a centre or
  // across the axis, so every lane misses.)
  // Both ends turned at once, a in lane 0 and b in lane 1 (v + 2w (q x v) + 2 q x (q x v)).
  using namespace simd;
  const EndLanes v = end_lanes(capsule);
  const Lanes vx = v.x, vy = v.y, vz = v.z;
  const Lanes qx = splat(xf.q.x), qy = splat(xf.q.y), qz = splat(xf.q.z), qw = splat(xf.q.w);
  Lanes tx = qy * vz - qz * vy, ty = qz * vx - qx * vz, tz = qx * vy - qy * vx;
  tx = tx + tx, ty = ty + ty, tz = tz + tz;
  const Lanes rx = vx + qw * tx + (qy * tz - qz * ty), ry = vy + qw * ty + (qz * tx - qx * tz),
              rz = vz + qw * tz + (qx * ty - qy * tx);
  // raycast_local on a capsule with the turned ends makes the same choice, but through it the
  // cast measured 44-46 -> 53-54 ns (bench_ray_cast3, stop 59): GCC lays the inlined lanes out
  // worse there.
  const Vec3 m = ray.origin - xf.p;
  const Vec3 d = ray.translation;
  const LocalHit3 h = detail::is_round(capsule.radius) ? capsule_cast<true, kNormal>(rx, ry, rz, capsule.radius, m, d)
                                                       : capsule_cast<false, kNormal>(rx, ry, rz, capsule.radius, m, d);
  return world_hit(h, ray, h.normal);
}

RayHit3 raycast_placed(const Capsule3& capsule, const Transform3& xf, const Ray3& ray) noexcept {
  return capsule_placed<true>(capsule, xf, ray);
}

/// A ball looks the same in every frame: only the origin is made relative to the centre, as
/// (origin - p) - R c so that large coordinates cancel first. No rotation of the ray or the
/// normal.
RayHit3 raycast_placed(const Sphere& sphere, const Transform3& xf, const Ray3& ray) noexcept {
  const Vec3 m = (ray.origin - xf.p) - rotate(xf.q, sphere.center);
  const LocalHit3 h = detail::ray_ball<3>(m, ray.translation, sphere.radius);
  return world_hit(h, ray, h.normal);
}

}  // namespace

template <Shape3DType S>
RayHit3 raycast(const S& shape, const Transform3& xf, const Ray3& ray) noexcept {
  return raycast_placed(shape, xf, ray);
}

template RayHit3 raycast(const Sphere&, const Transform3&, const Ray3&) noexcept;
template RayHit3 raycast(const Capsule3&, const Transform3&, const Ray3&) noexcept;
template RayHit3 raycast(const Segment3&, const Transform3&, const Ray3&) noexcept;
template RayHit3 raycast(const Box&, const Transform3&, const Ray3&) noexcept;
template RayHit3 raycast(const ConvexHull&, const Transform3&, const Ray3&) noexcept;

RayHit3 raycast(const Shape3D& shape, const Transform3& xf, const Ray3& ray) noexcept {
  return std::visit([&](const auto& s) { return raycast(s, xf, ray); }, shape);
}

// As in 2D (raycast.cpp): raycast_placed flattened into each, the point and normal dead code, the
// hit and fraction raycast's own instructions (no fused multiply-adds in this file either).
template <Shape3DType S>
COLLIDE_FLATTEN RayFraction raycast_fraction(const S& shape, const Transform3& xf, const Ray3& ray) noexcept {
  // The capsule's fraction comes from its lanes by a shorter path than the normal's piece index
  // (capsule_cast): the same value, picked otherwise.
  RayHit3 h;
  if constexpr (std::is_same_v<S, Capsule3>) {
    h = capsule_placed<false>(shape, xf, ray);
  } else {
    h = raycast_placed(shape, xf, ray);
  }
  return {h.hit, h.fraction};
}

template RayFraction raycast_fraction(const Sphere&, const Transform3&, const Ray3&) noexcept;
template RayFraction raycast_fraction(const Capsule3&, const Transform3&, const Ray3&) noexcept;
template RayFraction raycast_fraction(const Segment3&, const Transform3&, const Ray3&) noexcept;
template RayFraction raycast_fraction(const Box&, const Transform3&, const Ray3&) noexcept;
template RayFraction raycast_fraction(const ConvexHull&, const Transform3&, const Ray3&) noexcept;

RayFraction raycast_fraction(const Shape3D& shape, const Transform3& xf, const Ray3& ray) noexcept {
  return std::visit([&](const auto& s) { return raycast_fraction(s, xf, ray); }, shape);
}

}  // namespace collide
