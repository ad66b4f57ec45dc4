#include <collide/broad/loose_grid.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace collide {

namespace {

/// The kLooseCellQuantile quantile of the largest sides of (a sample of) the boxes, kept above
/// the float resolution of the world; points-only input falls back to suggest_cell_size.
template <int D>
float loose_cell_size(std::span<const AabbN<D>> boxes, const AabbN<D>& bounds,
                      std::vector<float>& scratch) {
  if (boxes.empty()) return 1.0f;
  sample_largest_sides(boxes, scratch);
  const auto at = static_cast<std::ptrdiff_t>(kLooseCellQuantile * static_cast<float>(scratch.size() - 1));
  std::nth_element(scratch.begin(), scratch.begin() + at, scratch.end());
  const float quantile = scratch[static_cast<std::size_t>(at)];
  if (!(quantile > 0.0f)) return suggest_cell_size(boxes, bounds, scratch);  // points only
  float magnitude = 0.0f;
  for (int k = 0; k < D; ++k) {
    magnitude = std::max({magnitude, std::abs(bounds.min[k]), std::abs(bounds.max[k])});
  }
  return std::max(quantile, kCellSizeResolution * magnitude);
}

template <int D>
using PackedBox = typename LooseGridN<D>::Packed;

/// The box as lanes (min, -max), zero padded (see LooseGridN::Packed).
template <int D>
PackedBox<D> pack(const AabbN<D>& box) noexcept {
  PackedBox<D> p{};
  constexpr int half = D == 2 ? 2 : 4;
  for (int k = 0; k < D; ++k) {
    p.lanes[k] = box.min[k];
    p.lanes[half + k] = -box.max[k];
  }
  return p;
}

template <int D>
AabbN<D> unpack(const PackedBox<D>& p) noexcept {
  constexpr int half = D == 2 ? 2 : 4;
  AabbN<D> box;
  for (int k = 0; k < D; ++k) {
    box.min[k] = p.lanes[k];
    box.max[k] = -p.lanes[half + k];
  }
  return box;
}

/// The lanes a packed box b is compared with to test it against `box`: (max, -min), so that
/// overlap(box, b) <=> b.min <= box.max and -b.max <= -box.min on every axis <=> every lane of
/// b <= the probe's (the zero pads compare 0 <= 0).
template <int D>
PackedBox<D> probe_of(const AabbN<D>& box) noexcept {
  return pack<D>({box.max, box.min});
}

/// Whether every lane of `b` is <= the matching lane of `probe`: overlap of the two boxes
/// (touching counts). NaN never occurs (the boxes are validated).
template <int D>
inline bool lanes_le(const PackedBox<D>& b, const PackedBox<D>& probe) noexcept {
#if defined(__SSE2__)
  const __m128 le = _mm_cmple_ps(_mm_load_ps(b.lanes), _mm_load_ps(probe.lanes));
  if constexpr (D == 2) {
    return _mm_movemask_ps(le) == 0xF;
  } else {
    const __m128 le2 = _mm_cmple_ps(_mm_load_ps(b.lanes + 4), _mm_load_ps(probe.lanes + 4));
    return _mm_movemask_ps(_mm_and_ps(le, le2)) == 0xF;
  }
#else
  bool all = true;
  for (std::size_t i = 0; i < std::size(b.lanes); ++i) all &= b.lanes[i] <= probe.lanes[i];
  return all;
#endif
}

}  // namespace

template <int D>
LooseGridN<D>::LooseGridN(Options options) : options_(options) {
  if (!(options_.cell_size >= 0.0f) || !std::isfinite(options_.cell_size)) {
    throw InvalidInput("LooseGrid: cell_size must be finite and >= 0 (0 chooses from the data)");
  }
  if (options_.band_bits < 0 || options_.band_bits > 31) {
    throw InvalidInput("LooseGrid: band_bits must be in [0, 31]");
  }
}

template <int D>
void LooseGridN<D>::build(std::span<const AabbN<D>> boxes) {
  const AabbN<D> bounds = checked_bounds_of(boxes);
  chosen_cell_size_ = options_.cell_size > 0.0f ? options_.cell_size
                                                : loose_cell_size(boxes, bounds, scratch_);
  rebuild(boxes, bounds);
}

template <int D>
void LooseGridN<D>::update(std::span<const AabbN<D>> boxes) {
  if (chosen_cell_size_ == 0.0f) {
    build(boxes);
    return;
  }
  rebuild(boxes, checked_bounds_of(boxes));
}

template <int D>
void LooseGridN<D>::rebuild(std::span<const AabbN<D>> boxes, const AabbN<D>& bounds) {
  count_ = static_cast<int>(boxes.size());
  // The grid: cells of the chosen size, widened until the cells with their border fit the
  // budget (and 32-bit keys).
  const std::uint64_t budget =
      std::min<std::uint64_t>(kCellsPerBox * boxes.size() + kMinCells, std::uint64_t{1} << 31);
  double size = chosen_cell_size_;
  for (;;) {
    grid_ = make_grid_mapping(bounds, static_cast<float>(size));
    double total = 1.0;
    for (int k = 0; k < D; ++k) total *= static_cast<double>(grid_.dims[k]) + 2.0;
    if (total <= static_cast<double>(budget)) break;
    size = std::max(static_cast<double>(grid_.cell_size) * 1.01,
                    static_cast<double>(grid_.cell_size) *
                        std::pow(total / static_cast<double>(budget), 1.0 / D));
  }
  std::uint32_t total_cells = 1;
  for (int k = 0; k < D; ++k) {
    padded_[k] = grid_.dims[k] + 2;
    total_cells *= static_cast<std::uint32_t>(padded_[k]);
  }

  // Each box's cell key, or kBigKey (and into big_) when it spans more than two cells.
  keys_.resize(boxes.size());
  big_.clear();
  std::uint32_t small = 0;
  const auto classify = [&](int i) {
    const CellN<D> lo = grid_.cell_of_inside(boxes[i].min);
    const CellN<D> hi = grid_.cell_of_inside(boxes[i].max);
    bool binned = true;
    for (int k = 0; k < D; ++k) binned &= hi[k] - lo[k] <= 1;
    if (!binned) {
      keys_[i] = kBigKey;
      big_.push_back({boxes[i], i});
      return kBigKey;
    }
    ++small;
    return keys_[i] = key_of(lo);
  };
  // Capacities for every box at once: a frame with a few more binned boxes than the last must
  // not double a vector (no allocation in the steady state, memory per object stays flat).
  starts_.reserve(budget + 2);
  packed_.reserve(boxes.size());
  ids_.reserve(boxes.size());
  const int band_bits = options_.band_bits;
  const std::uint32_t bands = ((total_cells - 1) >> band_bits) + 1;
  if (bands == 1) {
    // Counting sort. Pass 1 counts the boxes of each cell in starts_[key + 2]; the prefix sum
    // makes starts_[key + 1] the first slot of cell key; pass 2 puts each box at its cell's
    // next slot (ids ascending), moving starts_[key + 1] to the cell's end, so that afterwards
    // starts_[key] is the first slot of cell key and starts_[key + 1] its end.
    starts_.assign(total_cells + 2, 0u);
    std::uint32_t* starts = starts_.data();
    for (int i = 0; i < count_; ++i) {
      const std::uint32_t key = classify(i);
      if (key != kBigKey) ++starts[key + 2];
    }
    for (std::uint32_t c = 2; c < total_cells + 2; ++c) starts[c] += starts[c - 1];
    packed_.resize(small);
    ids_.resize(small);
    Packed* packed = packed_.data();
    int* ids = ids_.data();
    for (int i = 0; i < count_; ++i) {
      const std::uint32_t key = keys_[i];
      if (key == kBigKey) continue;
      const std::uint32_t slot = starts[key + 1]++;
      packed[slot] = pack<D>(boxes[i]);
      ids[slot] = i;
    }
  } else {
    // The same counting sort in two steps, so that its random accesses stay in cache on large
    // grids: the boxes are first distributed (stably) into bands of 2^band_bits consecutive
    // cells, packed with their key and id; then the per-cell count and placement run band after
    // band, touching one band's cell starts and slots at a time.
    band_starts_.assign(bands + 1, 0u);
    for (int i = 0; i < count_; ++i) {
      const std::uint32_t key = classify(i);
      if (key != kBigKey) ++band_starts_[(key >> band_bits) + 1];
    }
    for (std::uint32_t b = 1; b <= bands; ++b) band_starts_[b] += band_starts_[b - 1];
    staged_.reserve(boxes.size());
    staged_.resize(small);
    Staged* staged = staged_.data();
    for (int i = 0; i < count_; ++i) {
      const std::uint32_t key = keys_[i];
      if (key == kBigKey) continue;
      staged[band_starts_[key >> band_bits]++] = {pack<D>(boxes[i]), key, i};
    }
    starts_.assign(total_cells + 2, 0u);
    std::uint32_t* starts = starts_.data();
    for (std::uint32_t s = 0; s < small; ++s) ++starts[staged[s].key + 2];
    for (std::uint32_t c = 2; c < total_cells + 2; ++c) starts[c] += starts[c - 1];
    packed_.resize(small);
    ids_.resize(small);
    Packed* packed = packed_.data();
    int* ids = ids_.data();
    for (std::uint32_t s = 0; s < small; ++s) {
      const std::uint32_t slot = starts[staged[s].key + 1]++;
      packed[slot] = staged[s].box;
      ids[slot] = staged[s].id;
    }
  }
  big_by_x_.assign(big_.begin(), big_.end());
  std::sort(big_by_x_.begin(), big_by_x_.end(), [](const Entry& a, const Entry& b) {
    return a.box.min.x < b.box.min.x || (a.box.min.x == b.box.min.x && a.id < b.id);
  });
}

template <int D>
void LooseGridN<D>::find_pairs(PairList& pairs) const {
  pairs.clear();
  append_pairs(pairs);
}

template <int D>
void LooseGridN<D>::append_pairs(PairList& pairs) const {
  const PackedBox<D>* packed = packed_.data();
  const int* ids = ids_.data();
  // overlap(box with this probe and id, box f): the pair (min id, max id).
  const auto test = [&](const PackedBox<D>& probe, int id, std::uint32_t f) {
    if (lanes_le<D>(packed[f], probe)) pairs.emplace_back(std::min(id, ids[f]), std::max(id, ids[f]));
  };
  // Small against small. For the box at slot e of cell c, the forward half of its neighbourhood
  // is: the rest of its own cell and the next cell along x (slots e+1 up to the end of c + 1,
  // contiguous), then rows of three cells (x - 1 .. x + 1) above it: (y + 1, z) in 2D and 3D, and
  // in 3D (y - 1 .. y + 1, z + 1). Each unordered pair of neighbouring cells is visited once.
  const std::uint32_t total_cells = static_cast<std::uint32_t>(starts_.size()) - 2;
  const std::uint32_t nx = static_cast<std::uint32_t>(padded_[0]);
  std::uint32_t rows[4];
  int row_count = 0;
  rows[row_count++] = nx - 1;
  if constexpr (D == 3) {
    const std::uint32_t plane = nx * static_cast<std::uint32_t>(padded_[1]);
    rows[row_count++] = plane - nx - 1;
    rows[row_count++] = plane - 1;
    rows[row_count++] = plane + nx - 1;
  }
  const std::uint32_t* starts = starts_.data();
  for (std::uint32_t c = 0; c < total_cells; ++c) {
    const std::uint32_t begin = starts[c], end = starts[c + 1];
    if (begin == end) continue;  // only cells with the border around them hold boxes
    const std::uint32_t next_end = starts[c + 2];
    for (std::uint32_t e = begin; e < end; ++e) {
      const PackedBox<D> probe = probe_of<D>(unpack<D>(packed[e]));
      const int id = ids[e];
      for (std::uint32_t f = e + 1; f < next_end; ++f) test(probe, id, f);
      for (int r = 0; r < row_count; ++r) {
        const std::uint32_t row = c + rows[r];
        const std::uint32_t row_end = starts[row + 3];
        for (std::uint32_t f = starts[row]; f < row_end; ++f) test(probe, id, f);
      }
    }
  }
  // Big against small: a small box meeting a big one has its min-corner cell in
  // [big lo - 1, big hi] (it spans at most two cells per axis).
  for (const Entry& b : big_) {
    const PackedBox<D> probe = probe_of<D>(b.box);
    for_each_run(grid_.cell_of_inside(b.box.min) - 1, grid_.cell_of_inside(b.box.max),
                 [&](std::uint32_t first, std::uint32_t last) {
                   for (std::uint32_t f = first; f < last; ++f) test(probe, b.id, f);
                   return true;
                 });
  }
  // Big against big: sweep along x.
  const std::size_t bigs = big_by_x_.size();
  for (std::size_t i = 0; i < bigs; ++i) {
    const Entry& a = big_by_x_[i];
    for (std::size_t j = i + 1; j < bigs && big_by_x_[j].box.min.x <= a.box.max.x; ++j) {
      const Entry& b = big_by_x_[j];
      if (overlap(a.box, b.box)) pairs.emplace_back(std::min(a.id, b.id), std::max(a.id, b.id));
    }
  }
}

template <int D>
template <class Visit>
bool LooseGridN<D>::for_each_run(const CellN<D>& lo, const CellN<D>& hi, Visit&& visit) const {
  if (packed_.empty()) return true;
  double cells = 1.0;
  for (int k = 0; k < D; ++k) cells *= static_cast<double>(hi[k] - lo[k] + 1);
  if (cells >= static_cast<double>(starts_.size())) {
    // Wider than the grid: every small box, each once, is cheaper than walking the rows.
    return visit(0u, static_cast<std::uint32_t>(packed_.size()));
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
  for (const Entry& b : big_) {
    if (overlap(b.box, box) && !callback(b.id)) return;
  }
  if (packed_.empty() || !overlap(box, grid_.bounds)) return;
  // cell_of clamps to the grid, and every binned box's cell is inside it.
  const PackedBox<D> probe = probe_of<D>(box);
  for_each_run(grid_.cell_of(box.min) - 1, grid_.cell_of(box.max),
               [&](std::uint32_t first, std::uint32_t last) {
                 for (std::uint32_t f = first; f < last; ++f) {
                   if (lanes_le<D>(packed_[f], probe) && !callback(ids_[f])) return false;
                 }
                 return true;
               });
}

template <int D>
void LooseGridN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  query(AabbN<D>{point, point}, callback);
}

template <int D>
void LooseGridN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  float limit = 1.0f;
  for (const Entry& b : big_) {
    if (limit <= 0.0f) return;
    if (ray_box_fraction(ray, b.box, limit) < 0.0f) continue;
    const float r = callback(b.id, limit);
    if (r < limit) limit = r;
  }
  if (limit <= 0.0f || packed_.empty()) return;
  // A small box with min-corner cell L lies within cells [L, L + 1]. Walking cell c, the boxes
  // that may cover it are those of cells c - {0,1}^D; each is tested at the first walked cell
  // inside its [L, L + 1] (the walk never re-enters a box of cells it left).
  bool first = true;
  CellN<D> previous{0};
  walk_cells(grid_, ray, limit, [&](const CellN<D>& cell, float max_fraction) {
    for (int corner = 0; corner < (1 << D) && max_fraction > 0.0f; ++corner) {
      CellN<D> from = cell;
      for (int k = 0; k < D; ++k) from[k] -= (corner >> k) & 1;
      const std::uint32_t key = key_of(from);
      for (std::uint32_t f = starts_[key]; f < starts_[key + 1] && max_fraction > 0.0f; ++f) {
        if (!first && cell_in_range<D>(previous, from, from + 1)) continue;
        if (ray_box_fraction(ray, unpack<D>(packed_[f]), max_fraction) < 0.0f) continue;
        const float r = callback(ids_[f], max_fraction);
        if (r < max_fraction) max_fraction = r;
      }
    }
    first = false;
    previous = cell;
    return max_fraction;
  });
}

template <int D>
std::size_t LooseGridN<D>::memory_bytes() const noexcept {
  return keys_.capacity() * sizeof(std::uint32_t) + starts_.capacity() * sizeof(std::uint32_t) +
         packed_.capacity() * sizeof(Packed) + ids_.capacity() * sizeof(int) +
         staged_.capacity() * sizeof(Staged) + band_starts_.capacity() * sizeof(std::uint32_t) + (big_.capacity() + big_by_x_.capacity()) * sizeof(Entry) +
         scratch_.capacity() * sizeof(float);
}

template class LooseGridN<2>;
template class LooseGridN<3>;

}  // namespace collide
