#pragma once
/// @file
/// Cyrus-Beck clipping of a ray by the half-spaces of a convex polytope, shared by the 2D
/// polygon and the 3D hull ray casts: one half-space at a time (clip_ray), and four at a time in
/// SSE2 lanes (ClipLanes) where random rays would mispredict the scalar loop. Internal to ccd.

#include <collide/core/math.hpp>

#include <algorithm>
#include <cstddef>
#include <limits>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif

namespace collide::detail {

/// Where a ray enters a convex polytope given by half-spaces.
struct ClipResult {
  int plane = -1;         ///< entering half-space (edge or face), -1 if none
  float fraction = 0.0f;  ///< entry fraction when plane >= 0
  bool inside = false;    ///< no entry because the origin lies in the closed polytope
};

/// Numerator and denominator of one half-space for the ray p + t d: num = offset - n . p
/// (>= 0 when p is inside), den = n . d; the ray is inside for t with t * den <= num.
struct PlaneCrossing {
  float num;
  float den;
};

/// Cyrus-Beck clipping of p + t d, t in [0, 1], by `count` half-spaces, half-space i given by
/// `crossing(i)` (Cyrus & Beck 1978; Ericson, Real-Time Collision Detection, 5.3.8). Entering
/// half-spaces (den < 0) raise the lower bound num / den, leaving ones (den > 0) lower the upper
/// bound. Bounds are kept as fractions with positive denominators so the loop never divides.
/// Returns the entering half-space, or -1 when the ray misses or starts inside (never enters);
/// then `inside` tells which. A ray with a NaN coordinate makes every crossing NaN: no bound
/// moves and the result says `inside`, which callers must not take for a hit.
template <class Crossing>
[[nodiscard]] inline ClipResult clip_ray(int count, Crossing&& crossing) noexcept {
  // lower = lo_num / lo_den, upper = up_num / up_den, denominators > 0.
  float lo_num = 0.0f, lo_den = 1.0f;
  float up_num = 1.0f, up_den = 1.0f;
  int entering = -1;
  for (int i = 0; i < count; ++i) {
    const PlaneCrossing c = crossing(i);
    if (c.den < 0.0f) {
      // Entering: t >= num / den = (-num) / (-den). Take it if above the lower bound.
      if (-c.num * lo_den > lo_num * -c.den) {
        lo_num = -c.num;
        lo_den = -c.den;
        entering = i;
      }
    } else if (c.den > 0.0f) {
      if (c.num * up_den < up_num * c.den) {  // leaving: t <= num / den
        up_num = c.num;
        up_den = c.den;
      }
    } else if (c.num < 0.0f) {
      return {};  // parallel and outside this half-space: never inside
    }
    if (up_num * lo_den < lo_num * up_den) return {};  // upper < lower: empty
  }
  // No entering half-space raised the lower bound above 0: the origin is inside every one.
  if (entering < 0) return {-1, 0.0f, true};
  return {entering, lo_num / lo_den, false};
}

#if defined(__SSE2__) || defined(_M_X64)
/// clip_ray's bounds kept four half-spaces at a time in SSE2 lanes, without branches: a stream of
/// fresh rays decides entering, leaving and which bound moves at random, and the scalar loop
/// mispredicts about once a half-space. Feed it each group's crossings with `add` (num and den
/// as clip_ray's, lanes past the last half-space repeating an earlier one), then `finish`. Each
/// bound is the division num / den rather than a comparison of cross products, so the entry
/// fraction is the value the scalar loop divides out at its end, and where two entering bounds
/// are equal within rounding (an edge or a corner) either half-space may be named: the first
/// holding the largest bound is (lowest index). An entering bound that rounds to 0 (an origin
/// on a plane within the smallest float) does not count as entering.
class ClipLanes {
 public:
  /// The next four half-spaces (0..3 at the first call, then 4..7, ...): their crossings num
  /// and den in lanes.
  void add(__m128 num, __m128 den) noexcept {
    const __m128 zero = _mm_setzero_ps();
    const __m128 t = _mm_div_ps(num, den);
    const __m128 entering = _mm_cmplt_ps(den, zero);
    const __m128 leaving = _mm_cmpgt_ps(den, zero);
    miss_ = _mm_or_ps(miss_, _mm_andnot_ps(_mm_or_ps(entering, leaving), _mm_cmplt_ps(num, zero)));
    // Strictly above the lane's best (a NaN bound never is): the earliest keeps a tie.
    const __m128 take = _mm_and_ps(entering, _mm_cmpgt_ps(t, best_));
    best_ = _mm_or_ps(_mm_and_ps(take, t), _mm_andnot_ps(take, best_));
    const __m128i take_i = _mm_castps_si128(take);
    best_index_ = _mm_or_si128(_mm_and_si128(take_i, index_), _mm_andnot_si128(take_i, best_index_));
    // min(candidate, upper) keeps upper when the candidate is NaN (the second operand wins).
    const __m128 infinity = _mm_set1_ps(std::numeric_limits<float>::infinity());
    upper_ = _mm_min_ps(_mm_or_ps(_mm_and_ps(leaving, t), _mm_andnot_ps(leaving, infinity)), upper_);
    index_ = _mm_add_epi32(index_, _mm_set1_epi32(4));
  }

  /// clip_ray's answer for the half-spaces added.
  [[nodiscard]] ClipResult finish() const noexcept {
    __m128 lower = _mm_max_ps(best_, _mm_shuffle_ps(best_, best_, _MM_SHUFFLE(1, 0, 3, 2)));
    lower = _mm_max_ps(lower, _mm_shuffle_ps(lower, lower, _MM_SHUFFLE(2, 3, 0, 1)));
    __m128 upper = _mm_min_ps(upper_, _mm_shuffle_ps(upper_, upper_, _MM_SHUFFLE(1, 0, 3, 2)));
    upper = _mm_min_ps(upper, _mm_shuffle_ps(upper, upper, _MM_SHUFFLE(2, 3, 0, 1)));
    const float entry = _mm_cvtss_f32(lower);
    if (_mm_movemask_ps(miss_) != 0 || _mm_cvtss_f32(upper) < entry) return {};
    if (!(entry > 0.0f)) return {-1, 0.0f, true};
    // The lowest index among the lanes holding the largest bound.
    const __m128i holds = _mm_castps_si128(_mm_cmpeq_ps(best_, lower));
    const __m128i none = _mm_set1_epi32(std::numeric_limits<int>::max());
    alignas(16) int lanes[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes),
                    _mm_or_si128(_mm_and_si128(holds, best_index_), _mm_andnot_si128(holds, none)));
    const int plane = std::min(std::min(lanes[0], lanes[1]), std::min(lanes[2], lanes[3]));
    return {plane, entry, false};
  }

 private:
  __m128 best_ = _mm_setzero_ps();                 ///< per lane: the largest entering bound
  __m128i best_index_ = _mm_set1_epi32(-1);        ///< and the first half-space holding it
  __m128 upper_ = _mm_set1_ps(1.0f);               ///< per lane: the smallest leaving bound
  __m128 miss_ = _mm_setzero_ps();                 ///< parallel, the origin outside
  __m128i index_ = _mm_setr_epi32(0, 1, 2, 3);     ///< the half-spaces of the next group
};

/// clip_ray over the edges of a convex 2D outline pushed out by `offset` (vertices[i] on edge i,
/// normals[i] its unit outward normal), four edges at a time in ClipLanes: the crossings
/// num = offset - n . (p - v), den = n . d, as the scalar loop forms them; the last group
/// repeats the last edge.
[[nodiscard]] inline ClipResult clip_ray_outline_lanes(const Vec2* vertices, const Vec2* normals,
                                                       int count, Vec2 p, Vec2 d,
                                                       float offset) noexcept {
  const __m128 px = _mm_set1_ps(p.x), py = _mm_set1_ps(p.y);
  const __m128 dx = _mm_set1_ps(d.x), dy = _mm_set1_ps(d.y);
  const __m128 voffset = _mm_set1_ps(offset);
  ClipLanes lanes;
  for (int i = 0; i < count; i += 4) {
    const int i1 = std::min(i + 1, count - 1), i2 = std::min(i + 2, count - 1);
    const int i3 = std::min(i + 3, count - 1);
    const __m128 nx = _mm_setr_ps(normals[i].x, normals[i1].x, normals[i2].x, normals[i3].x);
    const __m128 ny = _mm_setr_ps(normals[i].y, normals[i1].y, normals[i2].y, normals[i3].y);
    const __m128 vx = _mm_setr_ps(vertices[i].x, vertices[i1].x, vertices[i2].x, vertices[i3].x);
    const __m128 vy = _mm_setr_ps(vertices[i].y, vertices[i1].y, vertices[i2].y, vertices[i3].y);
    const __m128 num = _mm_sub_ps(voffset, _mm_add_ps(_mm_mul_ps(nx, _mm_sub_ps(px, vx)),
                                                      _mm_mul_ps(ny, _mm_sub_ps(py, vy))));
    lanes.add(num, _mm_add_ps(_mm_mul_ps(nx, dx), _mm_mul_ps(ny, dy)));
  }
  return lanes.finish();
}

/// clip_ray over 3D half-spaces stored four at a time (`blocks`: per block the normals' x of four
/// half-spaces, then their y, their z and their offsets, 16 floats; the last block padded by
/// repeating an earlier half-space), each offset raised by `extra`, in ClipLanes: the crossings
/// num = (offset + extra) - n . p, den = n . d, summed in the scalar loop's order.
[[nodiscard]] inline ClipResult clip_ray_blocks(const float* blocks, std::size_t block_count,
                                                float px, float py, float pz, float dx, float dy,
                                                float dz, float extra) noexcept {
  const __m128 vpx = _mm_set1_ps(px), vpy = _mm_set1_ps(py), vpz = _mm_set1_ps(pz);
  const __m128 vdx = _mm_set1_ps(dx), vdy = _mm_set1_ps(dy), vdz = _mm_set1_ps(dz);
  const __m128 vextra = _mm_set1_ps(extra);
  ClipLanes lanes;
  for (std::size_t b = 0; b < block_count; ++b) {
    const float* block = blocks + 16 * b;
    const __m128 nx = _mm_loadu_ps(block), ny = _mm_loadu_ps(block + 4);
    const __m128 nz = _mm_loadu_ps(block + 8), offset = _mm_loadu_ps(block + 12);
    const __m128 num = _mm_sub_ps(_mm_add_ps(offset, vextra),
                                  _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, vpx), _mm_mul_ps(ny, vpy)),
                                             _mm_mul_ps(nz, vpz)));
    const __m128 den = _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, vdx), _mm_mul_ps(ny, vdy)),
                                  _mm_mul_ps(nz, vdz));
    lanes.add(num, den);
  }
  return lanes.finish();
}
#endif

}  // namespace collide::detail
