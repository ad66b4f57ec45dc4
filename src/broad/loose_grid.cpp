#include <collide/broad/loose_grid.hpp>

#include <collide/core/error.hpp>

#include "x_sorted.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace collide {

namespace {

/// The `fraction` quantile of `sides` (the largest sides of a sample of the boxes, see
/// sample_largest_sides), kept above the float resolution of the world; points-only input falls
/// back to suggest_cell_size.
template <int D>
float loose_cell_size(std::span<const AabbN<D>> boxes, const AabbN<D>& bounds, float fraction,
                      std::vector<float>& sides) {
  if (sides.empty()) return 1.0f;
  const auto at = static_cast<std::ptrdiff_t>(fraction * static_cast<float>(sides.size() - 1));
  std::nth_element(sides.begin(), sides.begin() + at, sides.end());
  const float quantile = sides[static_cast<std::size_t>(at)];
  if (!(quantile > 0.0f)) return suggest_cell_size(boxes, bounds, sides);  // points only
  float magnitude = 0.0f;
  for (int k = 0; k < D; ++k) {
    magnitude = std::max({magnitude, std::abs(bounds.min[k]), std::abs(bounds.max[k])});
  }
  return std::min(std::max(quantile, kCellSizeResolution * magnitude), kMaxCellSize);
}

/// Boxes tested against one probe box at once: a group of SIMD lanes.
constexpr std::uint32_t kLanes = 4;

/// Bits [0, n) set, n clamped to kLanes: the lanes of a group that lie in a run of n entries.
inline std::uint32_t lane_mask(std::uint32_t n) noexcept {
  return (1u << std::min(n, kLanes)) - 1u;
}

/// For each 4-bit lane mask, the indices of its set bits, ascending, packed to the front (the
/// other lanes 0).
alignas(16) constexpr std::uint32_t kPacked[16][4] = {
    {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 2, 0, 0},
    {1, 2, 0, 0}, {0, 1, 2, 0}, {3, 0, 0, 0}, {0, 3, 0, 0}, {1, 3, 0, 0}, {0, 1, 3, 0},
    {2, 3, 0, 0}, {0, 2, 3, 0}, {1, 2, 3, 0}, {0, 1, 2, 3}};

/// Set bits of each 4-bit lane mask (std::popcount is a dozen instructions without POPCNT,
/// which baseline x86-64 lacks).
constexpr std::uint8_t kLaneCount[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

/// Bytes ahead of a sequential read that prefetch_ahead asks for: on a million boxes the
/// hardware prefetchers alone left the key pass waiting on memory (3.4 ns per 3D box with this,
/// 10 without, on the bench machine).
constexpr std::size_t kPrefetchBytes = 2048;

/// Asks for the cache line kPrefetchBytes after element i of data[0, n) (clamped to the last
/// element): a hint only.
template <class T>
inline void prefetch_ahead([[maybe_unused]] const T* data, [[maybe_unused]] std::size_t i,
                           [[maybe_unused]] std::size_t n) noexcept {
#if defined(__SSE2__)
  constexpr std::size_t kAhead = kPrefetchBytes / sizeof(T);
  _mm_prefetch(reinterpret_cast<const char*>(data + std::min(i + kAhead, n - 1)), _MM_HINT_T0);
#endif
}

/// std::copy of trivially copyable values into `to`, with streaming stores where the SIMD
/// path has them (from the first 16-byte aligned destination on).
template <class T>
void stream_copy(const T* from, const T* end, T* to) noexcept {
#if defined(__SSE2__)
  static_assert(16 % sizeof(T) == 0);
  for (; from != end && reinterpret_cast<std::uintptr_t>(to) % 16 != 0; ++from, ++to) *to = *from;
  constexpr std::size_t kPer = 16 / sizeof(T);
  for (; static_cast<std::size_t>(end - from) >= kPer; from += kPer, to += kPer) {
    _mm_stream_si128(reinterpret_cast<__m128i*>(to), _mm_loadu_si128(reinterpret_cast<const __m128i*>(from)));
  }
  _mm_sfence();
#endif
  std::copy(from, end, to);
}

/// Copies the kCount values at `from` (a 64-byte aligned buffer) to `to` (64-byte
/// aligned, whole cache lines) by streaming stores where the SIMD path has them; sfence()
/// orders them before later reads of `to`.
template <std::size_t kCount, class T>
inline void stream_line_impl(const T* from, T* to) noexcept {
  constexpr std::size_t kBytes = kCount * sizeof(T);
  static_assert(kBytes % 64 == 0);
#if defined(__SSE2__)
  const auto* f = reinterpret_cast<const __m128i*>(from);
  auto* t = reinterpret_cast<__m128i*>(to);
  for (std::size_t k = 0; k < kBytes / 16; ++k) _mm_stream_si128(t + k, _mm_load_si128(f + k));
#else
  std::copy(from, from + kCount, to);
#endif
}

inline void sfence() noexcept {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

/// values[i] += values[0] + ... + values[i - 1] for i in [1, count): the running sums.
void inclusive_prefix_sum(std::uint32_t* values, std::uint32_t count) noexcept {
  std::uint32_t i = 0;
#if defined(__SSE2__)
  // Four at a time: the sums within the four lanes by two shifted adds, plus the carry from the
  // lanes before (the last sum, in every lane).
  __m128i carry = _mm_setzero_si128();
  for (; i + 4 <= count; i += 4) {
    __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(values + i));
    v = _mm_add_epi32(v, _mm_slli_si128(v, 4));
    v = _mm_add_epi32(v, _mm_slli_si128(v, 8));
    v = _mm_add_epi32(v, carry);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(values + i), v);
    carry = _mm_shuffle_epi32(v, _MM_SHUFFLE(3, 3, 3, 3));
  }
  std::uint32_t sum = static_cast<std::uint32_t>(_mm_cvtsi128_si32(carry));
#else
  std::uint32_t sum = 0;
#endif
  for (; i < count; ++i) values[i] = sum += values[i];
}

/// A box, each coordinate repeated in every lane, to be tested against four stored boxes.
template <int D>
struct Probe {
#if defined(__SSE2__)
  __m128 min[D];
  __m128 max[D];
#else
  float min[D];
  float max[D];
#endif
};

template <int D>
Probe<D> probe_of(const AabbN<D>& box) noexcept {
  Probe<D> p;
  for (int k = 0; k < D; ++k) {
#if defined(__SSE2__)
    p.min[k] = _mm_set1_ps(box.min[k]);
    p.max[k] = _mm_set1_ps(box.max[k]);
#else
    p.min[k] = box.min[k];
    p.max[k] = box.max[k];
#endif
  }
  return p;
}

/// The probe of the box stored at entry e of the coordinate arrays (see overlap_mask).
template <int D>
Probe<D> probe_at(const float* coords, std::size_t stride, std::uint32_t e) noexcept {
  Probe<D> p;
  for (int k = 0; k < D; ++k) {
#if defined(__SSE2__)
    p.min[k] = _mm_set1_ps(coords[k * stride + e]);
    p.max[k] = _mm_set1_ps(coords[(D + k) * stride + e]);
#else
    p.min[k] = coords[k * stride + e];
    p.max[k] = coords[(D + k) * stride + e];
#endif
  }
  return p;
}

/// Overlap of the probe with the four stored boxes at entries f .. f + 3 of the coordinate
/// arrays (coordinate a of entry e at coords[a * stride + e]: min corner for a < D, max corner
/// for a >= D): bit j is set when entry f + j overlaps the probe on every axis,
///   min[k][f + j] <= probe.max[k]  and  probe.min[k] <= max[k][f + j]  for every k
/// (touching counts; the boxes are validated, so no NaN). Entries past a run are read (the
/// arrays are padded) and masked off by the caller.
template <int D>
inline std::uint32_t overlap_mask(const float* coords, std::size_t stride, std::uint32_t f,
                                  const Probe<D>& probe) noexcept {
  const float* p = coords + f;
#if defined(__SSE2__)
  __m128 in = _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(p), probe.max[0]),
                         _mm_cmpge_ps(_mm_loadu_ps(p + D * stride), probe.min[0]));
  for (int k = 1; k < D; ++k) {
    in = _mm_and_ps(in, _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(p + k * stride), probe.max[k]),
                                   _mm_cmpge_ps(_mm_loadu_ps(p + (D + k) * stride), probe.min[k])));
  }
  return static_cast<std::uint32_t>(_mm_movemask_ps(in));
#else
  std::uint32_t mask = 0;
  for (std::uint32_t j = 0; j < kLanes; ++j) {
    bool in = true;
    for (int k = 0; k < D; ++k) {
      in &= (p[k * stride + j] <= probe.max[k]) & (probe.min[k] <= p[(D + k) * stride + j]);
    }
    mask |= static_cast<std::uint32_t>(in) << j;
  }
  return mask;
#endif
}

/// Where a row of cells lies on one axis relative to the probe box's own cell: one below, the
/// same, one above.
enum class Side { kBelow, kSame, kAbove };

/// The four lanes of a group: all bits set in a lane that passed (SIMD), or bit j for lane j.
#if defined(__SSE2__)
using Lanes = __m128;
#else
using Lanes = std::uint32_t;
#endif

/// overlap_mask, restricted to the first n of the four entries, for stored boxes whose
/// min-corner cells lie on the side kY (and kZ in 3D) of the probe box's cell on y (and z),
/// as lanes. On an axis where that cell is above, the stored box's min is above the probe's
/// min (the cell mapping is monotone), so probe.min <= max is true already and only
/// min <= probe.max is tested; below, only probe.min <= max. The tests keep the loaded values
/// as their first operand (probe.min <= max written as !(max < probe.min): the same without
/// NaN), so SSE needs no register copies.
template <int D, Side kY, Side kZ>
inline Lanes run_lanes(const float* coords, std::size_t stride, std::uint32_t f, std::uint32_t n,
                       const Probe<D>& probe) noexcept {
  constexpr Side kSide[3] = {Side::kSame, kY, kZ};
  const float* p = coords + f;
#if defined(__SSE2__)
  // lane j is in the run when j < n (n as a signed int: runs are far shorter than 2^31)
  __m128 in = _mm_castsi128_ps(_mm_cmpgt_epi32(_mm_set1_epi32(static_cast<int>(n)), _mm_setr_epi32(0, 1, 2, 3)));
  for (int k = 0; k < D; ++k) {
    if (kSide[k] != Side::kBelow) in = _mm_and_ps(in, _mm_cmple_ps(_mm_loadu_ps(p + k * stride), probe.max[k]));
    if (kSide[k] != Side::kAbove) in = _mm_and_ps(in, _mm_cmpnlt_ps(_mm_loadu_ps(p + (D + k) * stride), probe.min[k]));
  }
  return in;
#else
  std::uint32_t mask = 0;
  for (std::uint32_t j = 0; j < std::min(n, kLanes); ++j) {
    bool in = true;
    for (int k = 0; k < D; ++k) {
      if (kSide[k] != Side::kBelow) in &= p[k * stride + j] <= probe.max[k];
      if (kSide[k] != Side::kAbove) in &= probe.min[k] <= p[(D + k) * stride + j];
    }
    mask |= static_cast<std::uint32_t>(in) << j;
  }
  return mask;
#endif
}

/// Bit 4r + j set when lane j of lanes[r] is: up to five groups in one mask.
template <int N>
inline std::uint32_t lane_bits(const Lanes (&lanes)[N]) noexcept {
#if defined(__SSE2__)
  // Four groups at a time narrowed to bytes (0 or -1 stays 0 or -1), one byte mask.
  const auto pack4 = [&](int r) {
    const auto at = [&](int i) { return r + i < N ? _mm_castps_si128(lanes[r + i]) : _mm_setzero_si128(); };
    const __m128i bytes = _mm_packs_epi16(_mm_packs_epi32(at(0), at(1)), _mm_packs_epi32(at(2), at(3)));
    return static_cast<std::uint32_t>(_mm_movemask_epi8(bytes));
  };
  if constexpr (N == 1) {
    return static_cast<std::uint32_t>(_mm_movemask_ps(lanes[0]));
  } else if constexpr (N <= 4) {
    return pack4(0);
  } else {
    static_assert(N <= 8);
    return pack4(0) | pack4(4) << 16;
  }
#else
  std::uint32_t mask = 0;
  for (int r = 0; r < N; ++r) mask |= lanes[r] << (kLanes * r);
  return mask;
#endif
}

}  // namespace

template <int D>
LooseGridN<D>::LooseGridN(Options options) : options_(options) {
  if (!(options_.cell_size >= 0.0f) || !std::isfinite(options_.cell_size)) {
    throw InvalidInput("LooseGrid: cell_size must be finite and >= 0 (0 chooses from the data)");
  }
  if (!(options_.cell_quantile > 0.0f && options_.cell_quantile <= 1.0f)) {
    throw InvalidInput("LooseGrid: cell_quantile must be in (0, 1]");
  }
  if (options_.band_bits < 0 || options_.band_bits > 31) {
    throw InvalidInput("LooseGrid: band_bits must be in [0, 31]");
  }
  if (options_.one_step_bits < 0 || options_.one_step_bits > 31) {
    throw InvalidInput("LooseGrid: one_step_bits must be in [0, 31]");
  }
}

template <int D>
void LooseGridN<D>::build(std::span<const AabbN<D>> boxes) {
  build_with(boxes, nullptr);
}

template <int D>
void LooseGridN<D>::update(std::span<const AabbN<D>> boxes) {
  update_with(boxes, nullptr);
}

template <int D>
void LooseGridN<D>::build_and_find_pairs(std::span<const AabbN<D>> boxes, PairList& pairs) {
  // (the entries of the last call are overwritten, not cleared first: see grow_pairs)
  PairSink sink{pairs, pairs.data(), 0, pairs.size()};
  try {
    build_with(boxes, &sink);
  } catch (...) {
    pairs.clear();
    throw;
  }
  finish_pairs(sink, pairs);
}

template <int D>
void LooseGridN<D>::update_and_find_pairs(std::span<const AabbN<D>> boxes, PairList& pairs) {
  // (the entries of the last call are overwritten, not cleared first: see grow_pairs)
  PairSink sink{pairs, pairs.data(), 0, pairs.size()};
  try {
    update_with(boxes, &sink);
  } catch (...) {
    pairs.clear();
    throw;
  }
  finish_pairs(sink, pairs);
}

template <int D>
void LooseGridN<D>::finish_pairs(PairSink& sink, PairList& pairs) {
  if (!small_pairs_done_) {
    append_small_range<false>(grid_view(), 0, small_, sink);
  } else {
    // Found band by band (find_big_in_band), each big box's in the order of its entries, as
    // append_big_pairs finds them: put in the order of the big boxes, stably, by a counting
    // sort into a buffer kept across calls (std::stable_sort allocates a buffer per call).
    big_found_starts_.assign(big_.size() + 1, 0u);
    for (const BigFound& f : big_found_) ++big_found_starts_[f.big + 1];
    for (std::size_t j = 0; j < big_.size(); ++j) big_found_starts_[j + 1] += big_found_starts_[j];
    big_found_sorted_.resize(big_found_.size());
    for (const BigFound& f : big_found_) big_found_sorted_[big_found_starts_[f.big]++] = f;
    big_found_.swap(big_found_sorted_);
  }
  append_big_pairs(sink);
  pairs.resize(sink.n);
}

template <int D>
void LooseGridN<D>::build_with(std::span<const AabbN<D>> boxes, PairSink* sink) {
  // The cell size and the grid from a sample of the boxes (all of them when few): a box outside
  // the sample's bounds (grown a little) is kept with the big ones, and when there are more
  // than outlier_limit such boxes the grid is laid over the exact bounds instead.
  try {
    const AabbN<D> sampled = sample_boxes(boxes, scratch_);
    chosen_cell_size_ = options_.cell_size > 0.0f ? options_.cell_size
                                                  : loose_cell_size(boxes, sampled, options_.cell_quantile, scratch_);
    set_grid(sampled, boxes.size());
    if (!bin(boxes, sink)) {
      // Over the exact bounds, a box is outside only beyond kGridCoordinateLimit: keep them all.
      set_grid(checked_bounds_of(boxes), boxes.size());
      bin(boxes, sink, true);
    }
  } catch (...) {
    clear();
    throw;
  }
}

template <int D>
void LooseGridN<D>::update_with(std::span<const AabbN<D>> boxes, PairSink* sink) {
  if (chosen_cell_size_ == 0.0f) {
    build_with(boxes, sink);
    return;
  }
  // The grid of the last call while it holds all but outlier_limit of the boxes (and fits the
  // cell budget); else one over the exact bounds grown by kUpdateMargin and a cell, so that
  // boxes moving on stay inside it for a while.
  try {
    if (cells_ <= cell_budget(boxes.size()) && bin(boxes, sink)) return;
    const AabbN<D> bounds = checked_bounds_of(boxes);
    const VecN<D> margin = kUpdateMargin * bounds.size() + VecN<D>(chosen_cell_size_);
    set_grid({bounds.min - margin, bounds.max + margin}, boxes.size());
    bin(boxes, sink, true);  // (outside only beyond kGridCoordinateLimit)
  } catch (...) {
    clear();
    throw;
  }
}

template <int D>
void LooseGridN<D>::clear() noexcept {
  // What find_pairs and the queries read, emptied; the grid and the capacities are kept.
  count_ = 0;
  small_ = 0;
  small_pairs_done_ = false;
  big_.clear();
  big_by_x_.clear();
  big_max_width_ = 0.0f;
  band_counts_.clear();
  std::fill(starts_.begin(), starts_.end(), 0u);
}

template <int D>
AabbN<D> LooseGridN<D>::sample_boxes(std::span<const AabbN<D>> boxes, std::vector<float>& sides) {
  // The boxes of sample_largest_sides: every box up to kCellSizeSamples, else box s * n /
  // kCellSizeSamples for each s (an even, deterministic stride; a shift, the count being a power
  // of two). Their largest sides to `sides`; their bounds, grown on each side by kSampleMargin
  // of their extent when not every box was sampled.
  static_assert(std::has_single_bit(static_cast<unsigned>(kCellSizeSamples)));
  constexpr int kShift = std::countr_zero(static_cast<unsigned>(kCellSizeSamples));
  const std::size_t n = boxes.size();
  if (n >= static_cast<std::size_t>(std::numeric_limits<int>::max())) validate_boxes(boxes);
  sides.clear();
  if (n == 0) return {};
  const std::size_t samples = std::min<std::size_t>(n, kCellSizeSamples);
  sides.resize(samples);
  VecN<D> lo = boxes[0].min, hi = boxes[0].max;
  bool good = true;
  for (std::size_t s = 0; s < samples; ++s) {
    const AabbN<D>& box = boxes[samples == n ? s : (s * n) >> kShift];
    good = good && is_valid_box(box);
    float largest = box.max[0] - box.min[0];
    for (int k = 0; k < D; ++k) {
      largest = std::max(largest, box.max[k] - box.min[k]);
      lo[k] = std::min(lo[k], box.min[k]);
      hi[k] = std::max(hi[k], box.max[k]);
    }
    sides[s] = largest;
  }
  if (!good) validate_boxes(boxes);  // throws, naming the first bad box
  if (samples == n) return {lo, hi};
  const VecN<D> margin = kSampleMargin * (hi - lo);
  return {lo - margin, hi + margin};
}

template <int D>
std::uint64_t LooseGridN<D>::cell_budget(std::size_t boxes) noexcept {
  return std::min<std::uint64_t>(kCellsPerBox * boxes + kMinCells, std::uint64_t{1} << 31);
}

template <int D>
void LooseGridN<D>::set_grid(const AabbN<D>& bounds, std::size_t boxes) {
  // Cells of the chosen size, widened until the cells with their border fit the budget (and
  // 32-bit keys).
  const std::uint64_t budget = cell_budget(boxes);
  double size = chosen_cell_size_;
  for (;;) {
    grid_ = make_grid_mapping(bounds, static_cast<float>(size));
    double total = 1.0;
    for (int k = 0; k < D; ++k) total *= static_cast<double>(grid_.dims[k]) + 2.0;
    // (at kMaxCellSize a grid has at most 8^D cells with the border, within every budget)
    if (total <= static_cast<double>(budget) || grid_.cell_size >= kMaxCellSize) break;
    size = std::max(static_cast<double>(grid_.cell_size) * 1.01,
                    static_cast<double>(grid_.cell_size) *
                        std::pow(total / static_cast<double>(budget), 1.0 / D));
  }
  band_counts_.clear();  // the bands of an earlier grid say nothing of this one
  cells_ = 1;
  for (int k = 0; k < D; ++k) {
    padded_[k] = grid_.dims[k] + 2;
    cells_ *= static_cast<std::uint32_t>(padded_[k]);
  }
}

template <int D>
template <class Count>
std::size_t LooseGridN<D>::compute_keys(std::span<const AabbN<D>> boxes, std::uint32_t big_key,
                                        bool store_keys, Count&& count) {
  // Scalar meaning, for each box i (the loop at the end, which also does the last boxes):
  //   inside = grid_.bounds contains the box, and min <= max on every axis (false for NaN)
  //   if !inside: a bad box (not finite, min > max) throws; else the box is an outlier
  //   lo = grid_.cell_of_inside(min), hi = grid_.cell_of_inside(max)
  //   binned = inside and hi[k] - lo[k] <= 1 on every axis
  //   key = binned ? key_of(lo) : big_key; count(key, i); if !binned, big_ gets the box;
  //   with store_keys, keys_[i] = key
  // key_of(lo) = sum over k of (lo[k] + 1) * stride[k], stride = (1, nx, nx * ny): the +1s
  // (the border) are the constant `base`. Returns the number of outliers.
  std::uint32_t stride[3] = {1, 0, 0};
  std::uint32_t base = 1;
  for (int k = 1; k < D; ++k) {
    stride[k] = stride[k - 1] * static_cast<std::uint32_t>(padded_[k - 1]);
    base += stride[k];
  }
  std::uint32_t* keys = keys_.data();
  const int n = count_;
  std::size_t outliers = 0;
  const AabbN<D> g = grid_.bounds;
  alignas(16) std::uint32_t four[4];  // the keys of four boxes when not stored
  // The boxes that are not binned: outliers (or bad boxes, which throw) and big ones.
  const auto not_binned = [&](int i, bool inside) {
    if (!inside) {
      const AabbN<D>& box = boxes[i];
      for (int k = 0; k < D; ++k) {
        if (!(std::isfinite(box.min[k]) && std::isfinite(box.max[k]) && box.min[k] <= box.max[k])) {
          validate_boxes(boxes);  // throws, naming the first bad box
        }
      }
      ++outliers;
    }
    big_.push_back({boxes[i], i});
  };
  int i = 0;
#if defined(__SSE2__)
  // Four boxes at a time, transposed so that each register holds one coordinate of the four:
  // the same float subtraction and multiplication as cell_of_inside, then truncation; the
  // inside test as above (every comparison is false for NaN).
  const __m128 inv = _mm_set1_ps(grid_.inv_cell_size);
  const __m128i one = _mm_set1_epi32(1);
  __m128 origin[D], lower[D], upper[D];
  __m128i cell_stride[D];
  for (int k = 0; k < D; ++k) {
    origin[k] = _mm_set1_ps(grid_.origin[k]);
    lower[k] = _mm_set1_ps(g.min[k]);
    upper[k] = _mm_set1_ps(g.max[k]);
    cell_stride[k] = _mm_set1_epi32(static_cast<int>(stride[k]));
  }
  const __m128i big = _mm_set1_epi32(static_cast<int>(big_key));
  const __m128i key_base = _mm_set1_epi32(static_cast<int>(base));
  // The low 32 bits of a * b in each lane (SSE2 has no such multiply: even and odd lanes apart).
  const auto mul_lo = [](__m128i a, __m128i b) {
    const __m128i even = _mm_mul_epu32(a, b);
    const __m128i odd = _mm_mul_epu32(_mm_srli_epi64(a, 32), _mm_srli_epi64(b, 32));
    return _mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                              _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0)));
  };
  for (; i + 4 <= n; i += 4) {
    const float* b0 = &boxes[i].min.x;
    _mm_prefetch(reinterpret_cast<const char*>(b0) + kPrefetchBytes, _MM_HINT_T0);
    __m128 lo[D], hi[D];
    // Rows (min.x, min.y, max.x, max.y) in 2D; (min.x, min.y, min.z, max.x) and
    // (min.z, max.x, max.y, max.z) in 3D.
    __m128 r0 = _mm_loadu_ps(b0), r1 = _mm_loadu_ps(b0 + 2 * D), r2 = _mm_loadu_ps(b0 + 4 * D),
           r3 = _mm_loadu_ps(b0 + 6 * D);
    _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
    if constexpr (D == 2) {
      lo[0] = r0, lo[1] = r1, hi[0] = r2, hi[1] = r3;
    } else {
      _mm_prefetch(reinterpret_cast<const char*>(b0) + kPrefetchBytes + 64, _MM_HINT_T0);
      const __m128 s0 = _mm_loadu_ps(b0 + 2), s1 = _mm_loadu_ps(b0 + 8), s2 = _mm_loadu_ps(b0 + 14),
                   s3 = _mm_loadu_ps(b0 + 20);
      const __m128 t01 = _mm_unpackhi_ps(s0, s1), t23 = _mm_unpackhi_ps(s2, s3);
      lo[0] = r0, lo[1] = r1, lo[2] = r2, hi[0] = r3;
      hi[1] = _mm_movelh_ps(t01, t23);  // max.y
      hi[2] = _mm_movehl_ps(t23, t01);  // max.z
    }
    __m128 inside = _mm_and_ps(_mm_cmple_ps(lower[0], lo[0]), _mm_cmple_ps(hi[0], upper[0]));
    inside = _mm_and_ps(inside, _mm_cmple_ps(lo[0], hi[0]));
    __m128i wide = _mm_setzero_si128();  // lanes spanning more than two cells on some axis
    __m128i key = key_base;
    for (int k = 0; k < D; ++k) {
      if (k > 0) {
        inside = _mm_and_ps(inside, _mm_and_ps(_mm_cmple_ps(lower[k], lo[k]), _mm_cmple_ps(hi[k], upper[k])));
        inside = _mm_and_ps(inside, _mm_cmple_ps(lo[k], hi[k]));
      }
      const __m128i cell_lo = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(lo[k], origin[k]), inv));
      const __m128i cell_hi = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(hi[k], origin[k]), inv));
      wide = _mm_or_si128(wide, _mm_cmpgt_epi32(_mm_sub_epi32(cell_hi, cell_lo), one));
      key = _mm_add_epi32(key, k == 0 ? cell_lo : mul_lo(cell_lo, cell_stride[k]));
    }
    const __m128i binned = _mm_andnot_si128(wide, _mm_castps_si128(inside));
    key = _mm_or_si128(_mm_and_si128(binned, key), _mm_andnot_si128(binned, big));
    std::uint32_t* to = store_keys ? keys + i : four;
    _mm_storeu_si128(reinterpret_cast<__m128i*>(to), key);
    for (int j = 0; j < 4; ++j) count(to[j], i + j);
    const int binned_lanes = _mm_movemask_ps(_mm_castsi128_ps(binned));
    if (binned_lanes != 0xF) [[unlikely]] {
      const int inside_lanes = _mm_movemask_ps(inside);
      for (int j = 0; j < 4; ++j) {
        if (!((binned_lanes >> j) & 1)) not_binned(i + j, (inside_lanes >> j) & 1);
      }
    }
  }
#endif
  for (; i < n; ++i) {
    const AabbN<D>& box = boxes[i];
    bool inside = true;
    for (int k = 0; k < D; ++k) {
      inside &= g.min[k] <= box.min[k] && box.min[k] <= box.max[k] && box.max[k] <= g.max[k];
    }
    bool binned = inside;
    std::uint32_t key = base;
    if (inside) {
      const CellN<D> lo = grid_.cell_of_inside(box.min);
      const CellN<D> hi = grid_.cell_of_inside(box.max);
      for (int k = 0; k < D; ++k) {
        binned &= hi[k] - lo[k] <= 1;
        key += static_cast<std::uint32_t>(lo[k]) * stride[k];
      }
    }
    key = binned ? key : big_key;
    if (store_keys) keys[i] = key;
    count(key, i);
    if (!binned) [[unlikely]] not_binned(i, inside);
  }
  return outliers;
}

template <int D>
bool LooseGridN<D>::bin(std::span<const AabbN<D>> boxes, PairSink* sink, bool every_outlier) {
  if (boxes.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max())) validate_boxes(boxes);
  count_ = static_cast<int>(boxes.size());
  small_pairs_done_ = false;
  // (a call that returned false wrote no pair: it stops before sorting)
  if (sink != nullptr) sink->n = 0;
  const std::uint32_t total_cells = cells_;
  // Big boxes share one bucket after every cell, so they sort after the binned ones.
  const std::uint32_t big_key = total_cells;
  const std::size_t max_outliers = every_outlier ? boxes.size() : outlier_limit(boxes.size());

  // Capacities for every box at once: a frame with a few more binned boxes than the last must
  // not double a vector (no allocation in the steady state, memory per object stays flat).
  keys_.resize(boxes.size());
  big_.clear();
  // A multiple of four, so that every coordinate array starts 16-byte aligned (streaming stores).
  stride_ = (boxes.size() + kPad + 3) & ~std::size_t{3};
  coords_.resize(2 * D * stride_);
  records_.resize(stride_);
  starts_.reserve(cell_budget(boxes.size()) + 3);
  Record* records = records_.data();
  const std::uint32_t* keys = keys_.data();
  const int band_bits = options_.band_bits;
  const std::uint32_t bands = ((total_cells - 1) >> band_bits) + 1;
  if (total_cells <= (std::uint64_t{1} << options_.one_step_bits) || bands == 1) {
    // Counting sort. Pass 1 counts the boxes of each cell in starts_[key + 2]; the prefix sum
    // makes starts_[key + 1] the first slot of cell key; pass 2 puts each record at its cell's
    // next slot (ids ascending), moving starts_[key + 1] to the cell's end, so that afterwards
    // starts_[key] is the first slot of cell key and starts_[key + 1] its end.
    starts_.assign(total_cells + 3, 0u);
    std::uint32_t* starts = starts_.data();
    if (compute_keys(boxes, big_key, true, [starts](std::uint32_t key, int) { ++starts[key + 2]; }) > max_outliers) {
      return false;
    }
    inclusive_prefix_sum(starts + 1, total_cells + 2);
    for (int i = 0; i < count_; ++i) {
      const std::uint32_t key = keys[i];
      records[starts[key + 1]++] = {key, i};
    }
    gather<false>(0, static_cast<std::uint32_t>(count_), [&](std::uint32_t e) -> const AabbN<D>& { return boxes[records[e].id]; });
  } else {
    // The same counting sort in two steps, so that its random accesses stay in cache on large
    // grids: the records are first distributed (stably) into bands of 2^band_bits consecutive
    // cells (the big bucket last); then each band is sorted by cell on its own (sort_band),
    // touching one band's cell starts and slots at a time, and its boxes are read in id order.
    // region[b]: where the records of band b are distributed (band `bands` is the big bucket).
    band_starts_.assign(bands + 2, 0u);
    std::uint32_t* region = band_starts_.data();
    const auto band_of = [=](std::uint32_t key) { return key == big_key ? bands : key >> band_bits; };
    // Each band's records and boxes go to its region, at the band's next slot. Regions start
    // and end on multiples of kLineSlots slots, and the record and box arrays on cache lines,
    // so a band's slots are written kLineSlots at a time from a line buffer in cache
    // (BandLine), by full-line streaming stores: no read of the lines before writing them
    // (software write-combining); `finish` writes the partly filled lines left.
    constexpr std::uint32_t kRound = kLineSlots - 1;
    band_lines_.resize(bands + 1);
    std::uint32_t* next = nullptr;
    Record* to = nullptr;
    AabbN<D>* staged = nullptr;
    // Room for the regions of either distribution below: a count's regions take at most
    // room(count) slots (the update's slack, every band rounded up to whole lines). Reserved
    // for this call's and the last call's counts at once, and only when that exceeds the
    // capacity, so that calls with slightly different band counts (every build) do not
    // reallocate the records and staged boxes each time (a fresh 8-24 MB at a million boxes).
    const auto room = [bands](std::size_t count) {
      return count + count / 8 + std::size_t{16 + kRound} * (bands + 1);
    };
    std::size_t last_count = 0;
    for (const std::uint32_t c : band_counts_) last_count += c;
    const auto start_regions = [&] {
      // (reserved first: resize alone may double the capacity)
      records_.reserve(std::max({stride_, std::size_t{region[bands + 1]}, room(std::max<std::size_t>(last_count, boxes.size()))}));
      records_.resize(std::max<std::size_t>(stride_, region[bands + 1]));
      stage_like_records();
      band_next_.assign(region, region + bands + 1);
      next = band_next_.data();
      to = records_.data();
      staged = staged_.data();
    };
    const auto place = [&](std::uint32_t b, std::uint32_t key, int i) {
      const std::uint32_t slot = next[b]++;
      BandLine& line = band_lines_.data()[b];
      line.records[slot % kLineSlots] = {key, i};
      line.boxes[slot % kLineSlots] = boxes[i];
      if (slot % kLineSlots == kRound) {
        stream_line_impl<kLineSlots>(line.records, to + (slot - kRound));
        stream_line_impl<kLineSlots>(line.boxes, staged + (slot - kRound));
      }
    };
    const auto finish = [&] {
      sfence();
      for (std::uint32_t b = 0; b <= bands; ++b) {
        const BandLine& line = band_lines_[b];
        const std::uint32_t filled = next[b] % kLineSlots, from = next[b] - filled;
        std::copy(line.records, line.records + filled, to + from);
        std::copy(line.boxes, line.boxes + filled, staged + from);
      }
    };
    bool distributed = false;
    if (band_counts_.size() == bands + 1) {
      // Update on the grid of a last call that was sorted by band: each band's region is sized
      // from its count then, with slack, so the key pass writes each record straight there
      // (no pass counting the bands first, no stored keys). A band that outgrew its region
      // falls back to the counting below.
      std::uint32_t at = 0;
      for (std::uint32_t b = 0; b <= bands; ++b) {
        region[b] = at;
        at += (band_counts_[b] + band_counts_[b] / 8 + 16 + kRound) & ~kRound;
      }
      region[bands + 1] = at;  // at most room(last_count)
      start_regions();
      bool overflow = false;
      if (compute_keys(boxes, big_key, false, [&](std::uint32_t key, int i) {
            const std::uint32_t b = band_of(key);
            if (next[b] == region[b + 1]) [[unlikely]] {
              overflow = true;
              return;
            }
            place(b, key, i);
          }) > max_outliers) {
        return false;
      }
      finish();
      distributed = !overflow;
      if (distributed) {
        for (std::uint32_t b = 0; b <= bands; ++b) band_counts_[b] = next[b] - region[b];
      } else {
        big_.clear();
      }
    }
    if (!distributed) {
      // Count the boxes of each band, then distribute them to consecutive regions.
      band_counts_.assign(bands + 1, 0u);
      std::uint32_t* counts = band_counts_.data();
      if (compute_keys(boxes, big_key, true, [=](std::uint32_t key, int) { ++counts[band_of(key)]; }) > max_outliers) {
        band_counts_.clear();
        return false;
      }
      region[0] = 0;
      for (std::uint32_t b = 0; b <= bands; ++b) region[b + 1] = region[b] + ((counts[b] + kRound) & ~kRound);
      start_regions();
      for (int i = 0; i < count_; ++i) {
        const std::uint32_t key = keys[i];
        place(band_of(key), key, i);
      }
      finish();
    }
    records = records_.data();
    // Each band sorted to the slots after the band before: at or before its region, so no
    // band overwrites one not sorted yet.
    starts_.resize(total_cells + 3);
    starts_[0] = 0;
    std::uint32_t slot = 0;
    // With a sink, each band's pairs are found right after it is sorted, from its copies in
    // window_, up to the entries whose forward neighbourhood reaches into the next band: the
    // entry of cell c needs the cell starts up to c + reach + 2 (its last row above ends at
    // c + reach + 1), and those of a band are known up to its last cell + 1 (the next band's
    // first cell's start). `pending`: the first entry whose pairs are not found yet (in 3D a
    // multiple of kPairChunk, so that the chunks and the order of the pairs are find_pairs').
    Window* window = sink != nullptr ? &window_ : nullptr;
    const std::uint32_t reach = static_cast<std::uint32_t>(D == 2 ? padded_[0] : padded_[0] * padded_[1] + padded_[0]);
    std::uint32_t pending = 0;
    if (window != nullptr) list_big_by_band(bands);
    for (std::uint32_t b = 0; b < bands; ++b) {
      const std::uint32_t first_cell = b << band_bits;
      const std::uint32_t last_cell = std::min(total_cells, first_cell + (std::uint32_t{1} << band_bits));
      if (window != nullptr) slide_window(pending, slot, band_counts_[b], first_cell, last_cell);
      sort_band(boxes, region[b], band_counts_[b], slot, first_cell, last_cell, window);
      slot += band_counts_[b];
      if (window == nullptr) continue;
      // Entries of cells below `limit` have their whole neighbourhood sorted (the last band:
      // every entry, the top rows being the empty border).
      std::uint32_t done = slot;
      if (b + 1 < bands) {
        done = pending;
        if (last_cell >= reach + 1 && last_cell - reach - 1 >= window_.cell0) {
          const std::uint32_t limit = last_cell - reach - 1;
          done = window_.starts[limit - window_.cell0];
          if constexpr (D == 3) done &= ~(kPairChunk - 1);
          done = std::max(done, pending);
        }
      }
      const PairView view{window_.coords.data(), window_.stride, window_.records.data(),
                          window_.starts.data(), window_.entry0, window_.cell0};
      append_small_range<true>(view, pending, done, *sink);
      find_big_in_band(b, first_cell, last_cell);
      pending = done;
    }
    small_pairs_done_ = window != nullptr;
    // The big bucket, in id order; the one-step sort leaves its end in the two last cell starts.
    std::copy(records + region[bands], records + region[bands] + band_counts_[bands], records + slot);
    gather<false>(slot, static_cast<std::uint32_t>(count_), [&](std::uint32_t e) -> const AabbN<D>& { return boxes[records[e].id]; });
    starts_[total_cells + 1] = starts_[total_cells + 2] = static_cast<std::uint32_t>(count_);
  }
  small_ = starts_[total_cells];
  big_by_x_.assign(big_.begin(), big_.end());
  std::sort(big_by_x_.begin(), big_by_x_.end(), [](const Entry& a, const Entry& b) {
    return a.box.min.x < b.box.min.x || (a.box.min.x == b.box.min.x && a.id < b.id);
  });
  big_max_width_ = 0.0f;
  for (const Entry& b : big_) big_max_width_ = std::max(big_max_width_, b.box.max.x - b.box.min.x);
  return true;
}

template <int D>
void LooseGridN<D>::slide_window(std::uint32_t pending, std::uint32_t first, std::uint32_t m,
                                 std::uint32_t first_cell, std::uint32_t last_cell) {
  Window& w = window_;
  // Kept: entries [pending, first) and cells [c0, first_cell), moved to the front.
  const std::uint32_t keep = first - pending;
  const std::uint32_t c0 = keep > 0 ? w.records[pending - w.entry0].key : first_cell;
  const std::size_t entries = std::size_t{keep} + m + kPad;
  const std::uint32_t from = pending - w.entry0;
  if (entries > w.stride) {
    // (grown by a quarter, so that it settles after a few calls)
    const std::size_t stride = (entries + entries / 4 + 3) & ~std::size_t{3};
    std::vector<float> coords(2 * D * stride);
    for (int a = 0; a < 2 * D && keep > 0; ++a) {
      std::copy_n(w.coords.begin() + static_cast<std::ptrdiff_t>(a * w.stride + from), keep,
                  coords.begin() + static_cast<std::ptrdiff_t>(a * stride));
    }
    w.coords.swap(coords);
    w.stride = stride;
  } else if (keep > 0 && from > 0) {
    for (int a = 0; a < 2 * D; ++a) {
      float* row = w.coords.data() + a * w.stride;
      std::copy(row + from, row + from + keep, row);
    }
  }
  if (keep > 0 && from > 0) std::copy(w.records.begin() + from, w.records.begin() + from + keep, w.records.begin());
  if (w.records.size() < keep + m) w.records.resize(keep + m);
  const std::uint32_t kept_cells = first_cell - c0;
  if (kept_cells > 0 && c0 > w.cell0) {
    const auto at = w.starts.begin() + (c0 - w.cell0);
    std::copy(at, at + kept_cells, w.starts.begin());
  }
  if (w.starts.size() < last_cell - c0 + 2) w.starts.resize(last_cell - c0 + 2);
  w.starts[kept_cells] = first;  // starts_[first_cell]: the end of the band before
  w.entry0 = pending;
  w.cell0 = c0;
}

template <int D>
void LooseGridN<D>::sort_band(std::span<const AabbN<D>> boxes, std::uint32_t from_slot,
                              std::uint32_t m, std::uint32_t first, std::uint32_t first_cell,
                              std::uint32_t last_cell, Window* window) {
  // records_[from_slot, from_slot + m) holds the band's records in id order, their cells in
  // [first_cell, last_cell); they go to slots [first, first + m), first <= from_slot. The
  // counting sort of bin's one-step path on the band's cell starts (starts_[first_cell] is the
  // end of the band before, set already), into copies that stay in cache: the cell starts,
  // the records placed there by cell and their boxes, read from staged_ at the records' slots
  // (one sequential sweep); then all are written out, with streaming stores (a million boxes
  // do not stay in cache until the pair pass anyway).
  // The band's cell starts are counted in a copy that stays in cache, cell[c - first_cell]
  // for starts_[c], and written out to starts_[first_cell + 1, last_cell + 2) at the end, by
  // streaming stores (no read of starts_'s lines before writing them).
  // With a window, its copies are used (they stay there for the pair pass).
  const std::uint32_t cells = last_cell - first_cell;
  std::uint32_t* cell = nullptr;
  if (window != nullptr) {
    cell = window->starts.data() + (first_cell - window->cell0);
  } else {
    band_cells_.resize(cells + 2);
    cell = band_cells_.data();
  }
  cell[1] = first;
  std::fill(cell + 2, cell + cells + 2, 0u);
  Record* records = records_.data();
  const Record* from = records + from_slot;
  const std::uint32_t last = first + m;
  for (std::uint32_t s = 0; s < m; ++s) {
    prefetch_ahead(from, s, m);
    ++cell[from[s].key - first_cell + 2];
  }
  inclusive_prefix_sum(cell + 1, cells + 1);
  // The next slot of the cell of `key` (moving it on: afterwards cell[c + 1] ends cell c).
  const auto slot_of = [cell, first_cell](std::uint32_t key) { return cell[key - first_cell + 1]++; };
  std::uint32_t* starts = starts_.data();
  // placed[slot - first]: the record of that slot.
  Record* placed = nullptr;
  float* window_coords = nullptr;
  if (window != nullptr) {
    placed = window->records.data() + (first - window->entry0);
    window_coords = window->coords.data() + (first - window->entry0);
  } else {
    band_records_.resize(m);
    placed = band_records_.data();
  }
  if (m > kBandCopy) {
    // A crowded band: its boxes straight from the span.
    for (std::uint32_t s = 0; s < m; ++s) placed[slot_of(from[s].key) - first] = from[s];
    stream_copy(cell + 1, cell + cells + 2, starts + first_cell + 1);
    std::copy(placed, placed + m, records + first);
    const auto box_of = [&](std::uint32_t e) -> const AabbN<D>& { return boxes[records[e].id]; };
    if (window != nullptr) {
      gather<false, true>(first, last, box_of, window_coords, window->stride);
    } else {
      gather<false>(first, last, box_of);
    }
    return;
  }
  // The band's boxes, staged by the key pass at the same slots as its records (a sequential
  // read), placed by cell into a copy that stays in cache.
  band_boxes_.resize(m);
  AabbN<D>* sorted = band_boxes_.data();
  const AabbN<D>* staged = staged_.data() + from_slot;
  for (std::uint32_t s = 0; s < m; ++s) {
    prefetch_ahead(staged, s, m);
    const std::uint32_t at = slot_of(from[s].key) - first;
    placed[at] = from[s];
    sorted[at] = staged[s];
  }
  stream_copy(cell + 1, cell + cells + 2, starts + first_cell + 1);
  // (The band's records are read up to here and overwritten only now.)
  stream_copy(placed, placed + m, records + first);
  const auto box_of = [&](std::uint32_t e) -> const AabbN<D>& { return sorted[e - first]; };
  if (window != nullptr) {
    gather<true, true>(first, last, box_of, window_coords, window->stride);
  } else {
    gather<true>(first, last, box_of);
  }
}

template <int D>
template <bool kStream, bool kWindow, class BoxOf>
void LooseGridN<D>::gather(std::uint32_t first, std::uint32_t last, BoxOf&& box_of,
                           [[maybe_unused]] float* window,
                           [[maybe_unused]] std::size_t window_stride) noexcept {
  // Scalar meaning: for each entry e in [first, last), coordinate k of the min corner of
  // box_of(e) to coords_[k * stride_ + e], of the max corner to coords_[(D + k) * stride_ + e]
  // (and with kWindow, to window[k * window_stride + e - first], window[(D + k) * ...]).
  // The writes are sequential; with kStream, streaming stores to coords_ (not kept in cache).
  float* coords = coords_.data();
  const std::size_t stride = stride_;
  std::uint32_t e = first;
  const auto copy_one = [&](std::uint32_t at) {
    const AabbN<D>& box = box_of(at);
    for (int k = 0; k < D; ++k) {
      coords[k * stride + at] = box.min[k];
      coords[(D + k) * stride + at] = box.max[k];
      if constexpr (kWindow) {
        window[k * window_stride + at - first] = box.min[k];
        window[(D + k) * window_stride + at - first] = box.max[k];
      }
    }
  };
#if defined(__SSE2__)
  // Streaming stores need 16-byte aligned addresses: entries up to a multiple of four first
  // (every array starts aligned, the stride being a multiple of four).
  if constexpr (kStream) {
    for (; e < last && e % 4 != 0; ++e) copy_one(e);
  }
  // Coordinate a of entries e .. e + 3.
  const auto store = [&](int a, __m128 v) {
    if constexpr (kStream) {
      _mm_stream_ps(coords + a * stride + e, v);
    } else {
      _mm_storeu_ps(coords + a * stride + e, v);
    }
    if constexpr (kWindow) _mm_storeu_ps(window + a * window_stride + (e - first), v);
  };
  // Four boxes at a time, transposed in registers: one four-wide store per coordinate.
  for (; e + 4 <= last; e += 4) {
    const float* b0 = &box_of(e).min.x;
    const float* b1 = &box_of(e + 1).min.x;
    const float* b2 = &box_of(e + 2).min.x;
    const float* b3 = &box_of(e + 3).min.x;
    // Rows (min.x, min.y, max.x, max.y) in 2D; (min.x, min.y, min.z, max.x) in 3D.
    __m128 r0 = _mm_loadu_ps(b0), r1 = _mm_loadu_ps(b1), r2 = _mm_loadu_ps(b2), r3 = _mm_loadu_ps(b3);
    _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
    if constexpr (D == 2) {
      store(0, r0);  // min x
      store(1, r1);  // min y
      store(2, r2);  // max x
      store(3, r3);  // max y
    } else {
      // (min.z, max.x, max.y, max.z) for the last two coordinates.
      __m128 s0 = _mm_loadu_ps(b0 + 2), s1 = _mm_loadu_ps(b1 + 2), s2 = _mm_loadu_ps(b2 + 2),
             s3 = _mm_loadu_ps(b3 + 2);
      _MM_TRANSPOSE4_PS(s0, s1, s2, s3);
      store(0, r0);  // min x
      store(1, r1);  // min y
      store(2, r2);  // min z
      store(3, r3);  // max x
      store(4, s2);  // max y
      store(5, s3);  // max z
    }
  }
  if constexpr (kStream) _mm_sfence();
#endif
  for (; e < last; ++e) copy_one(e);
}

template <int D>
void LooseGridN<D>::find_pairs(PairList& pairs) const {
  pairs.clear();
  append_pairs(pairs);
}

namespace {

/// (min(a, b), max(a, b)) without a comparison the compiler could turn into a branch: ids are
/// in [0, 2^31 - 1), so a - b does not overflow.
inline BroadPair ordered_pair(int a, int b) noexcept {
  const int d = a - b;
  const int below = d & (d >> 31);  // d when a < b, else 0
  return {b + below, a - below};
}

/// Grows `pairs` to at least `size` entries, by an eighth and 4096 at least; returns its data.
/// The new entries are value-initialised (written once more), so a list refilled from the
/// size of the last call grows by a little; the capacity itself grows geometrically
/// (std::vector::resize past it).
[[gnu::noinline]] BroadPair* grow_pairs(PairList& pairs, std::size_t size) {
  pairs.resize(std::max(size, pairs.size() + pairs.size() / 8 + 4096));
  return pairs.data();
}

}  // namespace

template <int D>
struct LooseGridN<D>::PairSink {
  PairList& pairs;
  BroadPair* out;
  std::size_t n;     // pairs written
  std::size_t room;  // pairs.size(): writes below it need no growth

  void reserve(std::size_t extra) {
    if (n + extra > room) [[unlikely]] {
      out = grow_pairs(pairs, n + extra);
      room = pairs.size();
    }
  }
};

template <int D>
template <std::uint32_t kRowMask, bool kListed, bool kWindow>
void LooseGridN<D>::append_small_pairs(const PairView& view, const std::uint32_t* list,
                                       std::uint32_t first_index, std::uint32_t last_index,
                                       PairSink& sink) const {
  // The runs of the forward half of an entry's neighbourhood (see append_pairs): its own row
  // from entry e + 1 to the end of the next cell along x, then the rows of three cells
  // (x - 1 .. x + 1) at these offsets from its cell, those of kRowMask only.
  const std::ptrdiff_t nx = padded_[0];
  const std::ptrdiff_t plane = D == 3 ? nx * padded_[1] : 0;
  const std::ptrdiff_t all_rows[4] = {nx - 1, plane - nx - 1, plane - 1, plane + nx - 1};
  // The sides of row r of all_rows on y and z (see run_lanes).
  constexpr Side kRowY[4] = {Side::kAbove, Side::kBelow, Side::kSame, Side::kAbove};
  constexpr Side kRowZ[4] = {Side::kSame, Side::kAbove, Side::kAbove, Side::kAbove};
  constexpr int kRows = std::popcount(kRowMask);
  constexpr int kRuns = 1 + kRows;
  // kRowOf[R]: the index in all_rows of the R-th row of kRowMask.
  constexpr std::array<int, 4> kRowOf = [] {
    std::array<int, 4> of{};
    for (int r = 0, k = 0; r < 4; ++r) {
      if ((kRowMask >> r) & 1u) of[k++] = r;
    }
    return of;
  }();
  std::ptrdiff_t rows[kRows > 0 ? kRows : 1];
  for (int r = 0; r < kRows; ++r) rows[r] = all_rows[kRowOf[r]];
  // Entries are indices into the view's arrays: the grid's entry e is e - eb there, its cell c
  // is c - cb (0 and 0 on the grid's own arrays).
  const float* coords = view.coords;
  const std::size_t stride = view.stride;
  const Record* records = view.records;
  const std::uint32_t* starts = view.starts;
  const std::uint32_t eb = kWindow ? view.entry_base : 0u;
  const std::uint32_t cb = kWindow ? view.cell_base : 0u;
  // The entries are tested a block at a time; an entry with an overlap (or a run longer than
  // one group, kLonger) is noted as a hit, and the hits' pairs are written after the block, so
  // the test loop keeps no run bounds for the rare pairs.
  constexpr std::uint32_t kBlock = 256;
  constexpr std::uint32_t kLonger = 1u << 31;  // set below as (longer >= 8) << 31
  struct Hit {
    std::uint32_t entry;
    std::uint32_t mask;  // bit 4r + j: entry j of run r overlaps; kLonger: more to test
  };
  Hit hits[kBlock];
  for (std::uint32_t block = first_index; block < last_index; block += kBlock) {
    const std::uint32_t block_end = std::min(last_index, block + kBlock);
    std::uint32_t hit_count = 0;
    for (std::uint32_t i = block; i < block_end; ++i) {
      const std::uint32_t e = kListed ? list[i] : i;
      // starts of the entry's cell: cell[0] is its first entry, cell[1] its end.
      const std::uint32_t* cell = starts + (records[e].key - cb);
      const Probe<D> probe = probe_at<D>(coords, stride, e);
      // Bit 4r + j: entry j of run r overlaps. Run 0 is the own row from e + 1; each run tests
      // only what its row needs (see run_lanes): the own row is on the same side on every axis,
      // row r of all_rows on the sides kRowY[r], kRowZ[r]. `longer`: some run is longer than
      // one group exactly when some length + kLanes - 1 reaches 2 * kLanes (an OR of values
      // below that stays below it).
      Lanes lanes[kRuns];
      std::uint32_t length = cell[2] - (e + eb + 1);
      std::uint32_t longer = length + (kLanes - 1);
      lanes[0] = run_lanes<D, Side::kSame, Side::kSame>(coords, stride, e + 1, length, probe);
      const std::uint32_t* row = cell;  // the starts of row R's first cell: row[0] .. row[3]
      [&]<std::size_t... R>(std::index_sequence<R...>) {
        ((row = cell + rows[R], length = row[3] - row[0], longer |= length + (kLanes - 1),
          lanes[R + 1] = run_lanes<D, kRowY[kRowOf[R]], kRowZ[kRowOf[R]]>(coords, stride, row[0] - eb,
                                                                          length, probe)),
         ...);
      }(std::make_index_sequence<kRows>{});
      const std::uint32_t mask = lane_bits(lanes) | static_cast<std::uint32_t>(longer >= 2 * kLanes) << 31;
      hits[hit_count] = {e, mask};
      hit_count += mask != 0 ? 1u : 0u;
    }
    for (std::uint32_t h = 0; h < hit_count; ++h) {
      const std::uint32_t e = hits[h].entry;
      const Record record = records[e];
      const std::uint32_t* cell = starts + (record.key - cb);
      // first[kRuns] = e: the entry read for the sentinel bit below.
      std::uint32_t first[kRuns + 1], last[kRuns];
      first[0] = e + 1;
      last[0] = cell[2] - eb;
      for (int r = 0; r < kRows; ++r) {
        first[r + 1] = cell[rows[r]] - eb;
        last[r + 1] = cell[rows[r] + 3] - eb;
      }
      first[kRuns] = e;
      sink.reserve(kLanes * kRuns + 2);
      // Each set bit b is the pair with entry first[b / 4] + b % 4. The first two without a
      // branch (most hits have one or two; how many is not predictable): with fewer bits, the
      // sentinel bit 4 * kRuns picks entry e and the write is not kept.
      constexpr std::uint32_t kSentinel = 1u << (kLanes * kRuns);
      const auto entry_of = [&](std::uint32_t b) { return first[b / kLanes] + b % kLanes; };
      BroadPair* out = sink.out;
      std::size_t n = sink.n;
      std::uint32_t m = hits[h].mask & ~kLonger;
      for (int k = 0; k < 2; ++k) {
        out[n] = ordered_pair(record.id, records[entry_of(static_cast<std::uint32_t>(std::countr_zero(m | kSentinel)))].id);
        n += m != 0 ? 1u : 0u;
        m &= m - 1;
      }
      for (; m != 0; m &= m - 1) {
        out[n++] = ordered_pair(record.id, records[entry_of(static_cast<std::uint32_t>(std::countr_zero(m)))].id);
      }
      sink.n = n;
      if (hits[h].mask & kLonger) [[unlikely]] {
        const Probe<D> probe = probe_at<D>(coords, stride, e);
        for (int r = 0; r < kRuns; ++r) {
          for (std::uint32_t f = first[r] + kLanes; f < last[r]; f += kLanes) {
            sink.reserve(kLanes);
            for (std::uint32_t more = overlap_mask<D>(coords, stride, f, probe) & lane_mask(last[r] - f); more != 0; more &= more - 1) {
              sink.out[sink.n++] = ordered_pair(record.id, records[f + static_cast<std::uint32_t>(std::countr_zero(more))].id);
            }
          }
        }
      }
    }
  }
}

template <int D>
void LooseGridN<D>::append_pairs(PairList& pairs) const {
  // Pairs are written through a raw pointer into a list grown ahead of the writes (no
  // capacity test per pair), and the list is cut to the pairs written at the end.
  PairSink sink{pairs, pairs.data(), pairs.size(), pairs.size()};
  append_small_range<false>(grid_view(), 0, small_, sink);
  append_big_pairs(sink);
  pairs.resize(sink.n);
}

template <int D>
template <bool kWindow>
void LooseGridN<D>::append_small_range(const PairView& view, std::uint32_t begin,
                                       std::uint32_t end, PairSink& sink) const {
  // Small against small. For the entry e of cell c, the forward half of its neighbourhood is
  // runs of entries: the rest of its own cell and the next cell along x (entries e + 1 up to
  // the end of c + 1, contiguous), then rows of three cells (x - 1 .. x + 1) above it:
  // (y + 1, z) in 2D and 3D, and in 3D (y - 1 .. y + 1, z + 1). Each unordered pair of
  // neighbouring cells is visited once. Each run is tested four entries at a time; runs are
  // usually shorter, so one masked test covers most.
  const std::uint32_t eb = kWindow ? view.entry_base : 0u;
  if constexpr (D == 2) {
    append_small_pairs<0b1u, false, kWindow>(view, nullptr, begin - eb, end - eb, sink);
  } else {
    // A box b of a row above on axis k can meet the entry's box a only if a's max corner
    // reaches that row: a.max[k] >= b.min[k] and the cell mapping is monotone, so
    // cell(a.max)[k] >= cell(b.min)[k] > cell(a.min)[k]. So the entries are grouped, a chunk
    // at a time, by the axes y, z whose next cell their box reaches (its crossing class), and
    // each group skips the rows it cannot reach: (y + 1, z) needs y, the rows at z + 1 need z,
    // and (y + 1, z + 1) both. Chunks start at multiples of kPairChunk of the grid's entries,
    // so that the order of the pairs does not depend on how the entries are split in ranges.
    //
    // Scalar meaning of the grouping, for each entry e of the chunk:
    //   class = (cell(max.y) > cell(min.y)) | (cell(max.z) > cell(min.z)) << 1
    //   list[class] gets e
    // (cell as cell_of_inside). Four entries at a time: each class's lanes as a mask, its
    // entries packed to the front of one four-wide store, the list moved on by their number
    // (each list has four slots of slack).
    constexpr std::uint32_t kChunk = kPairChunk;
    std::uint32_t lists[4][kChunk + kLanes];
    [[maybe_unused]] const float* coords = view.coords;
    [[maybe_unused]] const std::size_t stride = view.stride;
    for (std::uint32_t chunk = begin; chunk < end; chunk += kChunk) {
      const std::uint32_t chunk_end = std::min(end, chunk + kChunk) - eb;
      std::uint32_t count[4] = {0, 0, 0, 0};
      std::uint32_t e = chunk - eb;
#if defined(__SSE2__)
      const __m128 inv = _mm_set1_ps(grid_.inv_cell_size);
      const auto crosses = [&](int k, std::uint32_t f) {
        const __m128 o = _mm_set1_ps(grid_.origin[k]);
        const __m128i lo = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(coords + k * stride + f), o), inv));
        const __m128i hi = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(coords + (D + k) * stride + f), o), inv));
        return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(hi, lo))));
      };
      for (; e + kLanes <= chunk_end; e += kLanes) {
        const std::uint32_t y = crosses(1, e), z = crosses(2, e);
        const std::uint32_t in_class[4] = {~(y | z) & 0xFu, y & ~z, z & ~y, y & z};
        const __m128i base = _mm_set1_epi32(static_cast<int>(e));
        for (int c = 0; c < 4; ++c) {
          const __m128i lanes = _mm_load_si128(reinterpret_cast<const __m128i*>(kPacked[in_class[c]]));
          _mm_storeu_si128(reinterpret_cast<__m128i*>(lists[c] + count[c]), _mm_add_epi32(base, lanes));
          count[c] += kLaneCount[in_class[c]];
        }
      }
#endif
      for (; e < chunk_end; ++e) {
        VecN<D> lo_corner, hi_corner;
        for (int k = 0; k < D; ++k) {
          lo_corner[k] = view.coords[k * view.stride + e];
          hi_corner[k] = view.coords[(D + k) * view.stride + e];
        }
        const CellN<D> lo = grid_.cell_of_inside(lo_corner), hi = grid_.cell_of_inside(hi_corner);
        const int c = (hi.y > lo.y ? 1 : 0) | (hi.z > lo.z ? 2 : 0);
        lists[c][count[c]++] = e;
      }
      append_small_pairs<0b0000u, true, kWindow>(view, lists[0], 0, count[0], sink);
      append_small_pairs<0b0001u, true, kWindow>(view, lists[1], 0, count[1], sink);
      append_small_pairs<0b0110u, true, kWindow>(view, lists[2], 0, count[2], sink);
      append_small_pairs<0b1111u, true, kWindow>(view, lists[3], 0, count[3], sink);
    }
  }
}

template <int D>
void LooseGridN<D>::append_big_pairs(PairSink& sink) const {
  std::size_t& n = sink.n;
  const Record* records = records_.data();
  const auto reserve = [&](std::size_t extra) { sink.reserve(extra); };
  BroadPair*& out = sink.out;
  if (small_pairs_done_) {
    // found by bin, band by band, and sorted by big box (finish_pairs)
    reserve(big_found_.size());
    for (const BigFound& f : big_found_) out[n++] = ordered_pair(big_[f.big].id, f.id);
  }
  // Big against small: a small box meeting a big one has its min-corner cell in
  // [big lo - 1, big hi] (it spans at most two cells per axis).
  // (cell_of clamps: a big box may be an outlier, outside the grid.)
  for (const Entry& b : small_pairs_done_ ? std::span<const Entry>{} : std::span<const Entry>{big_}) {
    for_each_run(grid_.cell_of(b.box.min) - 1, grid_.cell_of(b.box.max),
                 [&](std::uint32_t first, std::uint32_t last) {
                   return for_each_overlap(b.box, first, last, [&](std::uint32_t f) {
                     reserve(1);
                     out[n++] = ordered_pair(b.id, records[f].id);
                     return true;
                   });
                 });
  }
  // Big against big: sweep along x.
  const std::size_t bigs = big_by_x_.size();
  for (std::size_t i = 0; i < bigs; ++i) {
    const Entry& a = big_by_x_[i];
    for (std::size_t j = i + 1; j < bigs && big_by_x_[j].box.min.x <= a.box.max.x; ++j) {
      const Entry& b = big_by_x_[j];
      if (overlap(a.box, b.box)) {
        reserve(1);
        out[n++] = ordered_pair(a.id, b.id);
      }
    }
  }
}

template <int D>
void LooseGridN<D>::list_big_by_band(std::uint32_t bands) {
  // Each big box's cells as for_each_run visits them (its shortcut to every small box never
  // applies here: cell_of clamps, so the range has at most (dims + 1)^D cells, fewer than
  // starts_); from its first to its last key, the bands it meets.
  big_found_.clear();
  big_ranges_.resize(big_.size());
  big_band_starts_.assign(bands + 1, 0u);
  const int band_bits = options_.band_bits;
  const auto band_range = [&](const BigRange& r) -> std::pair<std::uint32_t, std::uint32_t> {
    return {key_of(r.lo) >> band_bits, std::min(bands - 1, key_of(r.hi) >> band_bits)};
  };
  for (std::size_t j = 0; j < big_.size(); ++j) {
    BigRange& r = big_ranges_[j];
    r.lo = grid_.cell_of(big_[j].box.min) - 1;
    r.hi = grid_.cell_of(big_[j].box.max);
    const auto [first, last] = band_range(r);
    for (std::uint32_t b = first; b <= last; ++b) ++big_band_starts_[b + 1];
  }
  for (std::uint32_t b = 0; b < bands; ++b) big_band_starts_[b + 1] += big_band_starts_[b];
  big_band_list_.resize(big_band_starts_[bands]);
  // (filled by moving each band's start on, then moved back)
  for (std::size_t j = 0; j < big_.size(); ++j) {
    const auto [first, last] = band_range(big_ranges_[j]);
    for (std::uint32_t b = first; b <= last; ++b) big_band_list_[big_band_starts_[b]++] = static_cast<std::uint32_t>(j);
  }
  for (std::uint32_t b = bands; b > 0; --b) big_band_starts_[b] = big_band_starts_[b - 1];
  big_band_starts_[0] = 0;
}

template <int D>
void LooseGridN<D>::find_big_in_band(std::uint32_t b, std::uint32_t first_cell, std::uint32_t last_cell) {
  const Window& w = window_;
  const float* coords = w.coords.data();
  const std::size_t stride = w.stride;
  const std::uint32_t eb = w.entry0;
  // The entries of cells [a, z] of the band (within [first_cell, last_cell)) that overlap
  // big box j, ascending, to big_found_.
  const auto test = [&](std::uint32_t j, std::uint32_t a, std::uint32_t z) {
    a = std::max(a, first_cell);
    z = std::min(z, last_cell - 1);
    if (a > z) return;
    const std::uint32_t first = w.starts[a - w.cell0] - eb, last = w.starts[z + 1 - w.cell0] - eb;
    const Probe<D> probe = probe_of<D>(big_[j].box);
    for (std::uint32_t f = first; f < last; f += kLanes) {
      for (std::uint32_t m = overlap_mask<D>(coords, stride, f, probe) & lane_mask(last - f); m != 0; m &= m - 1) {
        big_found_.push_back({j, w.records[f + static_cast<std::uint32_t>(std::countr_zero(m))].id});
      }
    }
  };
  for (std::uint32_t i = big_band_starts_[b]; i < big_band_starts_[b + 1]; ++i) {
    const std::uint32_t j = big_band_list_[i];
    const BigRange& r = big_ranges_[j];
    // Its rows, as for_each_run (keys ascending).
    if constexpr (D == 2) {
      for (int y = r.lo.y; y <= r.hi.y; ++y) test(j, key_of({r.lo.x, y}), key_of({r.hi.x, y}));
    } else {
      for (int z = r.lo.z; z <= r.hi.z; ++z) {
        for (int y = r.lo.y; y <= r.hi.y; ++y) test(j, key_of({r.lo.x, y, z}), key_of({r.hi.x, y, z}));
      }
    }
  }
}

template <int D>
template <class Report>
bool LooseGridN<D>::for_each_overlap(const AabbN<D>& box, std::uint32_t first,
                                     std::uint32_t last, Report&& report) const {
  const float* coords = coords_.data();
  const std::size_t stride = stride_;
  const Probe<D> probe = probe_of<D>(box);
  for (std::uint32_t f = first; f < last; f += kLanes) {
    for (std::uint32_t m = overlap_mask<D>(coords, stride, f, probe) & lane_mask(last - f); m != 0; m &= m - 1) {
      if (!report(f + static_cast<std::uint32_t>(std::countr_zero(m)))) return false;
    }
  }
  return true;
}

template <int D>
template <class Visit>
bool LooseGridN<D>::for_each_run(const CellN<D>& lo, const CellN<D>& hi, Visit&& visit) const {
  if (small_ == 0) return true;
  double cells = 1.0;
  for (int k = 0; k < D; ++k) cells *= static_cast<double>(hi[k] - lo[k] + 1);
  if (cells >= static_cast<double>(starts_.size())) {
    // Wider than the grid: every small box, each once, is cheaper than walking the rows.
    return visit(0u, small_);
  }
  const std::uint32_t* starts = starts_.data();
  if constexpr (D == 2) {
    for (int y = lo.y; y <= hi.y; ++y) {
      const std::uint32_t first = key_of({lo.x, y}), last = key_of({hi.x, y});
      if (!visit(starts[first], starts[last + 1])) return false;
    }
  } else {
    for (int z = lo.z; z <= hi.z; ++z) {
      for (int y = lo.y; y <= hi.y; ++y) {
        const std::uint32_t first = key_of({lo.x, y, z}), last = key_of({hi.x, y, z});
        if (!visit(starts[first], starts[last + 1])) return false;
      }
    }
  }
  return true;
}

template <int D>
void LooseGridN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  const auto min_x = [](const Entry& e) { return e.box.min.x; };
  if (!detail::visit_in_x_range(big_by_x_.begin(), big_by_x_.end(), box.min.x, box.max.x, big_max_width_, min_x,
                                [&](const Entry& b) { return !overlap(b.box, box) || callback(b.id); })) {
    return;
  }
  if (small_ == 0 || !overlap(box, grid_.bounds)) return;
  // cell_of clamps to the grid, and every binned box's cell is inside it.
  for_each_run(grid_.cell_of(box.min) - 1, grid_.cell_of(box.max),
               [&](std::uint32_t first, std::uint32_t last) {
                 return for_each_overlap(box, first, last,
                                         [&](std::uint32_t f) { return callback(records_[f].id); });
               });
}

template <int D>
void LooseGridN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  query(AabbN<D>{point, point}, callback);
}

template <int D>
void LooseGridN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  ray_cast(ray, SlabRayN<D>(ray), callback);
}

template <int D>
void LooseGridN<D>::ray_cast(const RayN<D>& ray, const SlabRayN<D>& slab, RayCallback callback) const {
  float limit = 1.0f;
  const float x_end = ray.origin.x + ray.translation.x;
  detail::visit_in_x_range(big_by_x_.begin(), big_by_x_.end(), std::min(ray.origin.x, x_end),
                           std::max(ray.origin.x, x_end), big_max_width_,
                           [](const Entry& e) { return e.box.min.x; }, [&](const Entry& b) {
                             if (slab.fraction(b.box, limit) >= 0.0f) {
                               const float r = callback(b.id, limit);
                               if (r < limit) limit = r;
                             }
                             return limit > 0.0f;
                           });
  if (limit <= 0.0f || small_ == 0) return;
  // A small box with min-corner cell L lies within cells [L, L + 1]. Walking cell c, the boxes
  // that may cover it are those of the lists of cells c - {0,1}^D; each list is tested at the
  // first walked cell inside its [L, L + 1] (the walk never re-enters a box of cells it left):
  // all of them at the first cell, then, after a step along axis a (the walk steps one axis at
  // a time), those whose L[a] is the layer the step entered (2 lists in 2D, 4 in 3D). The lists
  // of two x-neighbour cells are neighbours in memory: both new, they are tested as one run.
  // The boxes are tested four at a time from the coordinate arrays (for_each_touched).
  bool first = true;
  CellN<D> previous{0};
  const auto visit = [&](std::size_t f, float max_fraction) { return callback(records_[f].id, max_fraction); };
  walk_cells(grid_, ray, slab, limit, [&](const CellN<D>& cell, float max_fraction) {
    int axis = -1, new_bit = 0;  // the step's axis, and the corner bit along it of the new lists
    if (!first) {
      for (int k = 0; k < D; ++k) {
        if (cell[k] != previous[k]) axis = k, new_bit = cell[k] > previous[k] ? 0 : 1;
      }
    }
    first = false;
    previous = cell;
    const bool near = axis != 0 || new_bit == 0, left = axis != 0 || new_bit == 1;  // x corner 0 / 1
    for (int rest = 0; rest < (1 << (D - 1)) && max_fraction > 0.0f; ++rest) {
      if (axis > 0 && ((rest >> (axis - 1)) & 1) != new_bit) continue;
      CellN<D> from = cell;  // the list of corner (0, rest); (-1, rest) is the one before it
      for (int k = 1; k < D; ++k) from[k] -= (rest >> (k - 1)) & 1;
      const std::uint32_t key = key_of(from);
      const std::uint32_t begin = starts_[left ? key - 1 : key], end = starts_[near ? key + 1 : key];
      if (begin == end) continue;  // (most cells of a sparse world are empty)
      max_fraction = for_each_touched(slab, coords_.data(), stride_, begin, end, max_fraction, visit);
    }
    return max_fraction;
  });
}

template <int D>
std::size_t LooseGridN<D>::memory_bytes() const noexcept {
  return keys_.capacity() * sizeof(std::uint32_t) + starts_.capacity() * sizeof(std::uint32_t) +
         coords_.capacity() * sizeof(float) +
         records_.capacity() * sizeof(Record) +
         (band_starts_.capacity() + band_next_.capacity() + band_counts_.capacity() + band_cells_.capacity()) * sizeof(std::uint32_t) +
         (band_boxes_.capacity() + staged_.capacity()) * sizeof(AabbN<D>) +
         band_records_.capacity() * sizeof(Record) + band_lines_.capacity() * sizeof(BandLine) +
         window_.coords.capacity() * sizeof(float) + window_.records.capacity() * sizeof(Record) +
         window_.starts.capacity() * sizeof(std::uint32_t) +
         (big_.capacity() + big_by_x_.capacity()) * sizeof(Entry) +
         (big_found_.capacity() + big_found_sorted_.capacity()) * sizeof(BigFound) +
         (big_ranges_.capacity() * sizeof(BigRange)) +
         (big_band_starts_.capacity() + big_band_list_.capacity() + big_found_starts_.capacity()) * sizeof(std::uint32_t) +
         scratch_.capacity() * sizeof(float);
}

template class LooseGridN<2>;
template class LooseGridN<3>;

}  // namespace collide
