#pragma once
/// @file
/// The one interface every broad phase in collide shares (DESIGN.md "Broad phase").
///
/// A broad phase is built or updated from a span of AABBs whose ids are their indices. It
/// reports every overlapping pair (touching counts: boxes are closed) exactly once, as
/// (i, j) with i < j, in an order that depends only on the input (deterministic). It answers
/// AABB queries, point queries and ray casts. The structures are interchangeable: each is
/// tested to produce exactly the brute-force pair set, and a game picks by benchmark.
///
/// Callbacks are `FunctionRef`s: non-owning, no allocation, valid only during the call.

#include <collide/core/aabb.hpp>
#include <collide/core/config.hpp>
#include <collide/core/function_ref.hpp>
#include <collide/core/ray.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <concepts>
#include <cstddef>
#include <functional>
#include <memory>
#include <limits>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__SSE2__) || defined(_M_X64)
#include <xmmintrin.h>
#define COLLIDE_SLAB_LANES 1
#endif

namespace collide {

/// One overlapping pair of ids (indices into the span of boxes), first < second.
using BroadPair = std::pair<int, int>;

/// The output of `find_pairs`: cleared and refilled on each call, so a vector kept across frames
/// stops allocating once it has grown to the largest pair count.
using PairList = std::vector<BroadPair>;

/// Called with each id whose box overlaps (or contains) the query. Return true to go on,
/// false to stop the query.
using QueryCallback = FunctionRef<bool(int id)>;

/// Called with each id whose box the ray meets within [0, max_fraction], and the current
/// max_fraction. Return the new max_fraction (point = origin + fraction * translation): return
/// max_fraction to go on unchanged, a smaller value to clip the ray (e.g. the fraction at which
/// the exact shape was hit), 0 to stop. Values above the current max_fraction are ignored.
/// (Box2D and Jolt use the same convention.)
using RayCallback = FunctionRef<float(int id, float max_fraction)>;

/// What every broad phase offers, for D = 2 or 3. `build` takes a fresh set of boxes; `update`
/// takes the same objects (same count) after they moved and may reuse work (incremental
/// structures) or rebuild (grids). Both throw InvalidInput for a box with a non-finite
/// coordinate or min > max, naming the box index. `find_pairs` refills its output.
template <class T, int D>
concept BroadPhase =
    requires(T& bp, const T& cbp, std::span<const AabbN<D>> boxes, PairList& pairs,
             const AabbN<D>& box, const VecN<D>& point, const RayN<D>& ray, QueryCallback qcb,
             RayCallback rcb) {
      bp.build(boxes);
      bp.update(boxes);
      bp.find_pairs(pairs);
      cbp.query(box, qcb);
      cbp.query_point(point, qcb);
      cbp.ray_cast(ray, rcb);
      { cbp.size() } -> std::same_as<int>;
      { cbp.memory_bytes() } -> std::same_as<std::size_t>;
    };

/// True when the box has finite coordinates and min <= max on each axis (NaN fails): the test
/// validate_boxes makes of each box, for loops that check boxes as they go.
template <int D>
[[nodiscard]] inline bool is_valid_box(const AabbN<D>& b) noexcept {
  constexpr float kMax = std::numeric_limits<float>::max();
  unsigned good = 1;  // & on unsigned rather than &&: no branch per comparison
  for (int k = 0; k < D; ++k) {
    good &= unsigned{b.min[k] <= b.max[k]} & unsigned{b.min[k] >= -kMax} & unsigned{b.max[k] <= kMax};
  }
  return good != 0;
}

/// Throws InvalidInput unless every box has finite coordinates and min <= max on each axis, and
/// there are fewer than 2^31 - 1 boxes. The message names the first bad box, e.g.
/// "box 7: min.y > max.y" or "box 3: coordinate not finite".
template <int D>
void validate_boxes(std::span<const AabbN<D>> boxes);

/// A ray (point = origin + fraction * translation) prepared for many box tests: the slab
/// method's reciprocals of the translation made once, so a broad phase's walk over its boxes
/// divides once per ray instead of once per box and axis. `fraction` gives exactly
/// ray_box_fraction's value.
template <int D>
class SlabRayN {
 public:
  explicit SlabRayN(const RayN<D>& ray) noexcept : origin_(ray.origin) {
    for (int k = 0; k < D; ++k) {
      parallel_[k] = ray.translation[k] == 0.0f;
      any_parallel_ = any_parallel_ || parallel_[k];
      inverse_[k] = parallel_[k] ? 0.0f : 1.0f / ray.translation[k];
    }
  }
  /// Fraction in [0, max_fraction] at which the ray first touches the closed box; 0 when it
  /// starts inside; a negative value on a miss. Slab method (Kay & Kajiya 1986; Ericson,
  /// Real-Time Collision Detection, 5.3.3), written so an axis the ray does not move along
  /// (translation 0) needs the origin inside that slab, with no NaN.
  [[nodiscard]] float fraction(const AabbN<D>& box, float max_fraction) const noexcept {
    float t_exit = max_fraction;
    if (!any_parallel_) {
      // t_enter starts from a zero held in the object, not a literal: against a literal 0 GCC
      // makes the first axis's select a branch on whether the box's near side is ahead, which
      // mispredicts along a grid walk (perf: a sixth of a world ray at 1e4 bodies).
      float t_enter = start_;
      // Every axis by selects and one test at the end (the same value: t_enter only grows and
      // t_exit only shrinks, so a test failing at some axis fails at the last): the early
      // exits below mispredicted on the crowded cells of a grid, where most boxes miss.
      for (int k = 0; k < D; ++k) {
        const float t0 = (box.min[k] - origin_[k]) * inverse_[k];
        const float t1 = (box.max[k] - origin_[k]) * inverse_[k];
        const float near = t0 > t1 ? t1 : t0, far = t0 > t1 ? t0 : t1;
        t_enter = near > t_enter ? near : t_enter;
        t_exit = far < t_exit ? far : t_exit;
      }
      return t_enter <= t_exit ? t_enter : -1.0f;
    }
    float t_enter = 0.0f;
    for (int k = 0; k < D; ++k) {
      const float o = origin_[k];
      if (parallel_[k]) {
        if (o < box.min[k] || o > box.max[k]) return -1.0f;
        continue;
      }
      float t0 = (box.min[k] - o) * inverse_[k];
      float t1 = (box.max[k] - o) * inverse_[k];
      if (t0 > t1) std::swap(t0, t1);
      if (t0 > t_enter) t_enter = t0;
      if (t1 < t_exit) t_exit = t1;
      if (!(t_enter <= t_exit)) return -1.0f;
    }
    return t_enter;
  }

  /// Which of four boxes the ray touches within [0, max_fraction]: bit i set when
  /// fraction(*box[i], max_fraction) >= 0, the same decision (each box in a lane of SSE2, the
  /// axes in fraction's order with its selects as min / max, so the same values). A grid's walk
  /// tests the boxes of a cell four at a time this way: a quarter of the scalar test's
  /// instructions a box, or more (world ray casts at 1e4 bodies test about 60 boxes a ray).
  [[nodiscard]] unsigned touches4(const std::array<const AabbN<D>*, 4>& box, float max_fraction) const noexcept {
#if defined(COLLIDE_SLAB_LANES)
    if (!any_parallel_) {
      static_assert(sizeof(AabbN<D>) == 2 * D * sizeof(float), "a box is D min floats, then D max floats");
      // The boxes' floats as a lane per box: lo[k] / hi[k] hold min[k] / max[k] of the four.
      __m128 lo[D], hi[D];
      if constexpr (D == 2) {
        __m128 r0 = _mm_loadu_ps(&box[0]->min.x), r1 = _mm_loadu_ps(&box[1]->min.x);
        __m128 r2 = _mm_loadu_ps(&box[2]->min.x), r3 = _mm_loadu_ps(&box[3]->min.x);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        lo[0] = r0, lo[1] = r1, hi[0] = r2, hi[1] = r3;
      } else {
        // min.x min.y min.z max.x, then min.z max.x max.y max.z (both within the 24 bytes)
        __m128 r0 = _mm_loadu_ps(&box[0]->min.x), r1 = _mm_loadu_ps(&box[1]->min.x);
        __m128 r2 = _mm_loadu_ps(&box[2]->min.x), r3 = _mm_loadu_ps(&box[3]->min.x);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        const __m128 u01 = _mm_unpackhi_ps(_mm_loadu_ps(&box[0]->min.z), _mm_loadu_ps(&box[1]->min.z));
        const __m128 u23 = _mm_unpackhi_ps(_mm_loadu_ps(&box[2]->min.z), _mm_loadu_ps(&box[3]->min.z));
        lo[0] = r0, lo[1] = r1, lo[2] = r2, hi[0] = r3;
        hi[1] = _mm_movelh_ps(u01, u23);
        hi[2] = _mm_movehl_ps(u23, u01);
      }
      return touch_lanes(lo, hi, max_fraction);
    }
#endif
    unsigned hits = 0;
    for (unsigned i = 0; i < 4; ++i) hits |= unsigned{fraction(*box[i], max_fraction) >= 0.0f} << i;
    return hits;
  }

  /// touches4 for four consecutive boxes of a structure-of-arrays store (a grid's entries):
  /// min[k] of box i at coords[k * stride + i], max[k] at coords[(D + k) * stride + i], i in
  /// [0, 4). The same decisions; the lanes load straight from the store, no transpose.
  [[nodiscard]] unsigned touches4(const float* coords, std::size_t stride, float max_fraction) const noexcept {
#if defined(COLLIDE_SLAB_LANES)
    if (!any_parallel_) {
      __m128 lo[D], hi[D];
      for (int k = 0; k < D; ++k) {
        lo[k] = _mm_loadu_ps(coords + std::size_t(k) * stride);
        hi[k] = _mm_loadu_ps(coords + std::size_t(D + k) * stride);
      }
      return touch_lanes(lo, hi, max_fraction);
    }
#endif
    unsigned hits = 0;
    for (unsigned i = 0; i < 4; ++i) {
      AabbN<D> box;
      for (int k = 0; k < D; ++k) {
        box.min[k] = coords[std::size_t(k) * stride + i];
        box.max[k] = coords[std::size_t(D + k) * stride + i];
      }
      hits |= unsigned{fraction(box, max_fraction) >= 0.0f} << i;
    }
    return hits;
  }

 private:
#if defined(COLLIDE_SLAB_LANES)
  /// The slab test of four boxes in lanes (lo[k] / hi[k]: min[k] / max[k] of the four), for a
  /// ray that moves along every axis: fraction's selects as min / max, so the same values.
  [[nodiscard]] unsigned touch_lanes(const __m128 (&lo)[D], const __m128 (&hi)[D], float max_fraction) const noexcept {
    __m128 t_enter = _mm_set1_ps(start_);
    __m128 t_exit = _mm_set1_ps(max_fraction);
    for (int k = 0; k < D; ++k) {
      const __m128 o = _mm_set1_ps(origin_[k]), inv = _mm_set1_ps(inverse_[k]);
      const __m128 t0 = _mm_mul_ps(_mm_sub_ps(lo[k], o), inv);
      const __m128 t1 = _mm_mul_ps(_mm_sub_ps(hi[k], o), inv);
      // minps(a, b) is a < b ? a : b and maxps(a, b) a > b ? a : b: fraction's selects
      const __m128 near = _mm_min_ps(t1, t0), far = _mm_max_ps(t0, t1);
      t_enter = _mm_max_ps(near, t_enter);
      t_exit = _mm_min_ps(far, t_exit);
    }
    return static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(t_enter, t_exit)));
  }
#endif
  VecN<D> origin_;
  VecN<D> inverse_{0.0f};  // 1 / translation, 0 on the axes it does not move along
  std::array<bool, D> parallel_{};
  bool any_parallel_ = false;
  float start_ = 0.0f;  // the fraction a ray starts at (see fraction)
};

/// The loop of for_each_touched, for any store of boxes: over i in [0, n) in groups of four,
/// test4(g, max_fraction) the bits of the boxes g .. g + 3 the ray touches (bits at or past n
/// are ignored), box_of(i) box i (an AabbN) to test again one met after a visit shrank the
/// fraction, visit(i, max_fraction) as for_each_touched's.
template <int D, class Test4, class BoxOf, class Visit>
COLLIDE_ALWAYS_INLINE float for_each_touched_by_fours(const SlabRayN<D>& slab, std::size_t n, float max_fraction, Test4&& test4,
                                BoxOf&& box_of, Visit&& visit) {
  for (std::size_t g = 0; g < n && max_fraction > 0.0f; g += 4) {
    const std::size_t left = std::min<std::size_t>(n - g, 4);
    const float tested = max_fraction;
    for (unsigned hits = test4(g, tested) & ((1u << left) - 1u); hits != 0; hits &= hits - 1) {
      if (max_fraction <= 0.0f) break;
      const std::size_t i = g + static_cast<std::size_t>(std::countr_zero(hits));
      if (max_fraction != tested && slab.fraction(box_of(i), max_fraction) < 0.0f) continue;
      const float r = visit(i, max_fraction);
      if (r < max_fraction) max_fraction = r;
    }
  }
  return max_fraction;
}

/// A ray's walk over a list of boxes (a grid cell's, a leaf's): for i in [0, n), in order, while
/// max_fraction > 0, when the ray touches box_of(i) (an AabbN reference) within the current max
/// fraction, max_fraction = min(max_fraction, visit(i, max_fraction)); returns the final max
/// fraction. The boxes are tested four at a time (SlabRayN::touches4); one met after a visit
/// shrank the fraction is tested again against the new one, so the visits are exactly those of
/// a loop testing one box at a time with SlabRayN::fraction.
template <int D, class BoxOf, class Visit>
float for_each_touched(const SlabRayN<D>& slab, std::size_t n, float max_fraction, BoxOf&& box_of, Visit&& visit) {
  const auto test4 = [&](std::size_t g, float tested) {
    const std::size_t last = std::min(n, g + 4) - 1;  // (a short group repeats its last box)
    const std::array<const AabbN<D>*, 4> group{&box_of(g), &box_of(std::min(g + 1, last)),
                                               &box_of(std::min(g + 2, last)), &box_of(std::min(g + 3, last))};
    return slab.touches4(group, tested);
  };
  return for_each_touched_by_fours(slab, n, max_fraction, test4, box_of, visit);
}

/// for_each_touched over the boxes [first, last) of a structure-of-arrays store (as
/// SlabRayN::touches4's: coordinate k of box e's min corner at coords[k * stride + e], of its
/// max corner at coords[(D + k) * stride + e]); visit(e, max_fraction) gets the box's index in
/// the store. Up to three boxes past `last` are read (and ignored): the store must hold them.
template <int D, class Visit>
COLLIDE_ALWAYS_INLINE float for_each_touched(const SlabRayN<D>& slab, const float* coords, std::size_t stride, std::size_t first,
                       std::size_t last, float max_fraction, Visit&& visit) {
  const auto box_of = [&](std::size_t i) {
    AabbN<D> box;
    for (int k = 0; k < D; ++k) {
      box.min[k] = coords[std::size_t(k) * stride + first + i];
      box.max[k] = coords[std::size_t(D + k) * stride + first + i];
    }
    return box;
  };
  return for_each_touched_by_fours(
      slab, last - first, max_fraction,
      [&](std::size_t g, float tested) { return slab.touches4(coords + first + g, stride, tested); }, box_of,
      [&](std::size_t i, float max_fraction_now) { return visit(first + i, max_fraction_now); });
}

/// Fraction in [0, max_fraction] at which the ray first touches the closed box (SlabRayN's
/// `fraction`, for one box: a loop over many boxes prepares the ray once instead).
template <int D>
[[nodiscard]] float ray_box_fraction(const RayN<D>& ray, const AabbN<D>& box,
                                     float max_fraction) noexcept {
  return SlabRayN<D>(ray).fraction(box, max_fraction);
}

/// Sorts pairs lexicographically: the canonical order of the registry, the world and the tests.
/// Pairs of non-negative ids, 512 or more, by a radix sort on first * 2^w + second (w the bits
/// of the largest id: 3 or 4 passes of 11 bits for 1e4 to 1e6 objects; Knuth, TAOCP vol. 3,
/// 5.2.5), otherwise std::sort. `scratch` is storage reused across calls (a world sorts its
/// pairs every frame without allocating); the first form makes its own.
void sort_pairs(PairList& pairs);
void sort_pairs(PairList& pairs, PairList& scratch);

}  // namespace collide
