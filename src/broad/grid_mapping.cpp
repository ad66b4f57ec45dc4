#include <collide/broad/grid_mapping.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace collide {

template <int D>
AabbN<D> checked_bounds_of(std::span<const AabbN<D>> boxes) {
  if (boxes.empty()) {
    validate_boxes(boxes);
    return {};
  }
  // Scalar meaning: lo = min over the boxes of min, hi = max of max, and one flag for all
  // boxes: finite and ordered on every axis, written so NaN fails. The first bad box is named
  // by validate_boxes.
  constexpr float kMax = std::numeric_limits<float>::max();
  bool good = boxes.size() < static_cast<std::size_t>(std::numeric_limits<int>::max());
  const std::size_t n = boxes.size();
#if defined(__SSE2__)
  // One box in one or two registers; two sets of running bounds to halve the min/max chains.
  const __m128 max = _mm_set1_ps(kMax);
  const __m128 sign = _mm_set1_ps(-0.0f);
  __m128 ok = _mm_castsi128_ps(_mm_set1_epi32(-1));
  if constexpr (D == 2) {
    static_assert(sizeof(AabbN<2>) == 4 * sizeof(float));
    // v = (min.x, min.y, max.x, max.y): lanes (0, 1) against (2, 3) for the order; lanes 2 and
    // 3 compare max with itself (false only for NaN).
    const auto check = [&](__m128 v) {
      const __m128 ordered = _mm_cmple_ps(v, _mm_movehl_ps(v, v));
      const __m128 finite = _mm_cmple_ps(_mm_andnot_ps(sign, v), max);
      ok = _mm_and_ps(ok, _mm_and_ps(ordered, finite));
    };
    // Running min and max of v: the min corner ends in lo's lanes 0, 1, the max corner in
    // hi's lanes 2, 3 (two sets, even and odd boxes, so the min/max chains run in parallel).
    __m128 lo0 = _mm_loadu_ps(&boxes[0].min.x), hi0 = lo0, lo1 = lo0, hi1 = lo0;
    std::size_t i = 0;
    for (; i + 2 <= n; i += 2) {
      const __m128 v0 = _mm_loadu_ps(&boxes[i].min.x), v1 = _mm_loadu_ps(&boxes[i + 1].min.x);
      check(v0);
      check(v1);
      lo0 = _mm_min_ps(lo0, v0);
      hi0 = _mm_max_ps(hi0, v0);
      lo1 = _mm_min_ps(lo1, v1);
      hi1 = _mm_max_ps(hi1, v1);
    }
    if (i < n) {
      const __m128 v = _mm_loadu_ps(&boxes[i].min.x);
      check(v);
      lo0 = _mm_min_ps(lo0, v);
      hi0 = _mm_max_ps(hi0, v);
    }
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, _mm_min_ps(lo0, lo1));
    _mm_store_ps(h, _mm_max_ps(hi0, hi1));
    good &= _mm_movemask_ps(ok) == 0xF;
    if (!good) validate_boxes(boxes);  // throws
    return {{l[0], l[1]}, {h[2], h[3]}};
  } else {
    static_assert(sizeof(AabbN<3>) == 6 * sizeof(float));
    // a = (min.x, min.y, min.z, max.x), b = (min.z, max.x, max.y, max.z): the min corner in a's
    // lanes 0..2, the max corner in b's lanes 1..3; the order test compares a with
    // (max.x, max.y, max.z, max.x).
    __m128 lo = _mm_loadu_ps(&boxes[0].min.x), hi = _mm_loadu_ps(&boxes[0].min.z);
    for (std::size_t i = 0; i < n; ++i) {
      const float* f = &boxes[i].min.x;
      const __m128 a = _mm_loadu_ps(f), b = _mm_loadu_ps(f + 2);
      const __m128 t = _mm_shuffle_ps(b, a, _MM_SHUFFLE(3, 3, 3, 3));       // (b3, b3, a3, a3)
      const __m128 upper = _mm_shuffle_ps(b, t, _MM_SHUFFLE(2, 0, 2, 1));   // (b1, b2, b3, a3)
      const __m128 finite = _mm_and_ps(_mm_cmple_ps(_mm_andnot_ps(sign, a), max),
                                       _mm_cmple_ps(_mm_andnot_ps(sign, b), max));
      ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmple_ps(a, upper), finite));
      lo = _mm_min_ps(lo, a);
      hi = _mm_max_ps(hi, b);
    }
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    good &= _mm_movemask_ps(ok) == 0xF;
    if (!good) validate_boxes(boxes);  // throws
    return {{l[0], l[1], l[2]}, {h[1], h[2], h[3]}};
  }
#else
  VecN<D> lo = boxes[0].min, hi = boxes[0].max;
  for (const AabbN<D>& b : boxes) {
    for (int k = 0; k < D; ++k) {
      good &= (b.min[k] <= b.max[k]) & (b.min[k] >= -kMax) & (b.max[k] <= kMax);
      lo[k] = b.min[k] < lo[k] ? b.min[k] : lo[k];
      hi[k] = b.max[k] > hi[k] ? b.max[k] : hi[k];
    }
  }
  if (!good) validate_boxes(boxes);  // throws
  return {lo, hi};
#endif
}

template <int D>
void sample_largest_sides(std::span<const AabbN<D>> boxes, std::vector<float>& out) {
  out.clear();
  // Every box up to kCellSizeSamples, else an even stride through the span (deterministic).
  const std::size_t n = boxes.size();
  const std::size_t samples = std::min<std::size_t>(n, kCellSizeSamples);
  for (std::size_t s = 0; s < samples; ++s) {
    const VecN<D> size = boxes[s * n / samples].size();
    float largest = size[0];
    for (int k = 1; k < D; ++k) largest = std::max(largest, size[k]);
    out.push_back(largest);
  }
}

template <int D>
float suggest_cell_size(std::span<const AabbN<D>> boxes, std::vector<float>& scratch) {
  return suggest_cell_size(boxes, bounds_of(boxes), scratch);
}

template <int D>
float suggest_cell_size(std::span<const AabbN<D>> boxes, const AabbN<D>& world,
                        std::vector<float>& scratch) {
  if (boxes.empty()) return 1.0f;
  sample_largest_sides(boxes, scratch);
  auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(scratch.size() / 2);
  std::nth_element(scratch.begin(), mid, scratch.end());
  float size = 2.0f * *mid;

  const VecN<D> extent = world.size();
  float span = extent[0];
  float magnitude = 0.0f;
  for (int k = 0; k < D; ++k) {
    span = std::max(span, extent[k]);
    magnitude = std::max({magnitude, std::abs(world.min[k]), std::abs(world.max[k])});
  }
  if (!(size > 0.0f)) {
    // Points only: about one point per cell if they were spread evenly.
    const float per_axis = std::pow(static_cast<float>(boxes.size()), 1.0f / static_cast<float>(D));
    size = span / std::max(per_axis, 1.0f);
  }
  // A cell must stay well above the float spacing of the coordinates it divides, and finite
  // (boxes whose sides overflow float, wider than FLT_MAX, make the median infinite).
  const float resolution = kCellSizeResolution * std::max(magnitude, 1e-30f);
  return std::min(std::max({size, resolution, std::numeric_limits<float>::min()}), kMaxCellSize);
}

template AabbN<2> checked_bounds_of<2>(std::span<const AabbN<2>>);
template AabbN<3> checked_bounds_of<3>(std::span<const AabbN<3>>);
template void sample_largest_sides<2>(std::span<const AabbN<2>>, std::vector<float>&);
template void sample_largest_sides<3>(std::span<const AabbN<3>>, std::vector<float>&);
template float suggest_cell_size<2>(std::span<const AabbN<2>>, std::vector<float>&);
template float suggest_cell_size<3>(std::span<const AabbN<3>>, std::vector<float>&);
template float suggest_cell_size<2>(std::span<const AabbN<2>>, const AabbN<2>&, std::vector<float>&);
template float suggest_cell_size<3>(std::span<const AabbN<3>>, const AabbN<3>&, std::vector<float>&);

}  // namespace collide
