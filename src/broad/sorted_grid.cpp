#include <collide/broad/sorted_grid.hpp>

#include "oversized_boxes.hpp"

#include <collide/core/error.hpp>
#include <collide/core/radix_sort.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <tuple>

namespace collide {

template <int D>
SortedGridN<D>::SortedGridN(Options options) : options_(options) {
  if (!std::isfinite(options.cell_size) || options.cell_size < 0.0f) {
    throw InvalidInput("SortedGrid options cell_size: negative or not finite");
  }
  if (options.max_cells_per_box < 1) {
    throw InvalidInput("SortedGrid options max_cells_per_box: below 1");
  }
}

template <int D>
void SortedGridN<D>::build(std::span<const AabbN<D>> boxes) {
  const AabbN<D> bounds = checked_bounds_of(boxes);
  chosen_cell_size_ = options_.cell_size > 0.0f ? options_.cell_size
                                                : suggest_cell_size(boxes, bounds, scratch_);
  rebuild(boxes, bounds);
}

template <int D>
void SortedGridN<D>::update(std::span<const AabbN<D>> boxes) {
  if (chosen_cell_size_ == 0.0f) {
    build(boxes);
    return;
  }
  rebuild(boxes, checked_bounds_of(boxes));
}

template <int D>
void SortedGridN<D>::rebuild(std::span<const AabbN<D>> boxes, const AabbN<D>& bounds) {
  count_ = static_cast<int>(boxes.size());
  grid_ = make_grid_mapping(bounds, chosen_cell_size_);
  oversized_.clear();
  is_oversized_.assign(boxes.size(), 0);
  ranges_.resize(boxes.size());
  entry_total_ = 0;
  std::size_t binned = 0;
  const double max_cells = options_.max_cells_per_box;
  // Two copies of the loop, so that an ordinary world's (the whole world inside the grid) has
  // no test for boxes beyond kGridCoordinateLimit.
  const auto bin = [&]<bool kPartial>() {
    // (locals, not members, in the loop: the stores through them cannot alias the grid)
    const GridMapping<D> grid = grid_;
    CellRange* ranges = ranges_.data();
    std::size_t entries = 0, filled = 0;
    const int n = count_;
    for (int i = 0; i < n; ++i) {
      if constexpr (kPartial) {
        if (!contains(grid.bounds, boxes[i])) {
          // Beyond kGridCoordinateLimit: no cell (cell_of_inside is only for points inside).
          oversized_.push_back(i);
          is_oversized_[i] = 1;
          continue;
        }
      }
      const CellN<D> lo = grid.cell_of_inside(boxes[i].min);
      const CellN<D> hi = grid.cell_of_inside(boxes[i].max);
      double cells = 1.0;
      for (int k = 0; k < D; ++k) cells *= static_cast<double>(hi[k] - lo[k] + 1);
      if (cells > max_cells) {
        oversized_.push_back(i);
        is_oversized_[i] = 1;
        continue;
      }
      ranges[filled++] = {lo, hi, i};
      entries += static_cast<std::size_t>(cells);
    }
    entry_total_ = entries;
    binned = filled;
  };
  if (grid_.partial) {
    bin.template operator()<true>();
  } else {
    bin.template operator()<false>();
  }
  ranges_.resize(binned);
  if (oversized_.empty()) {
    boxes_.clear();
  } else {
    boxes_.assign(boxes.begin(), boxes.end());
  }
  fill(boxes);
}

template <int D>
void SortedGridN<D>::build_subset(std::span<const AabbN<D>> boxes, std::span<const int> ids,
                                  const GridMapping<D>& grid) {
  boxes_.clear();
  count_ = static_cast<int>(ids.size());
  oversized_.clear();
  is_oversized_.clear();
  grid_ = grid;
  ranges_.resize(ids.size());
  entry_total_ = 0;
  for (std::size_t r = 0; r < ids.size(); ++r) {
    const int id = ids[r];
    ranges_[r] = {grid_.cell_of_inside(boxes[id].min), grid_.cell_of_inside(boxes[id].max), id};
    std::size_t cells = 1;
    for (int k = 0; k < D; ++k) cells *= static_cast<std::size_t>(ranges_[r].hi[k] - ranges_[r].lo[k] + 1);
    entry_total_ += cells;
  }
  fill(boxes);
}

template <int D>
void SortedGridN<D>::fill(std::span<const AabbN<D>> boxes) {
  std::uint64_t total_cells = 1;  // below 2^62 (make_grid_mapping)
  for (int k = 0; k < D; ++k) total_cells *= static_cast<std::uint64_t>(grid_.dims[k]);
  dense_ = total_cells <= kDenseCellsPerBox * (ranges_.size() + 256);
  if (dense_) {
    fill_counting(boxes, total_cells);
    block_bits_.clear();
  } else {
    fill_radix(boxes, total_cells);
    mark_blocks();
  }
}

template <int D>
void SortedGridN<D>::mark_blocks() {
  // The finest blocks whose bitmap fits the budget (found by shift 30 at the latest: the grid
  // has fewer than 2^31 cells per axis, so at most 2 blocks per axis there).
  const std::uint64_t budget = kBlockBitsPerBox * (ranges_.size() + 64);
  std::uint64_t blocks = 1;
  for (block_shift_ = kMinBlockShift; block_shift_ < 31; ++block_shift_) {
    blocks = 1;
    for (int k = 0; k < D; ++k) {
      block_dims_[k] = static_cast<int>(((static_cast<std::uint64_t>(grid_.dims[k]) - 1) >> block_shift_) + 1);
      blocks *= static_cast<std::uint64_t>(block_dims_[k]);  // (at most budget * 2^29 < 2^64)
      if (blocks > budget) break;
    }
    if (blocks <= budget) break;
  }
  block_bits_.assign(static_cast<std::size_t>((blocks + 63) / 64), 0);
  if (block_shift_ == 0) {
    // A block is a cell: the bit is the cell's key, one per occupied cell (the runs).
    for (int r = 0; r < cell_count(); ++r) {
      const std::uint64_t key = runs_[static_cast<std::size_t>(r)].key;
      block_bits_[key >> 6] |= std::uint64_t{1} << (key & 63);
    }
    return;
  }
  for (const CellRange& r : ranges_) {
    CellN<D> lo, hi;
    for (int k = 0; k < D; ++k) {
      lo[k] = r.lo[k] >> block_shift_;
      hi[k] = r.hi[k] >> block_shift_;
    }
    for_each_cell<D>(lo, hi, [&](const CellN<D>& b) {
      std::uint64_t index = 0;
      for (int k = D - 1; k >= 0; --k) index = index * static_cast<std::uint64_t>(block_dims_[k]) + static_cast<std::uint64_t>(b[k]);
      block_bits_[index >> 6] |= std::uint64_t{1} << (index & 63);
      return true;
    });
  }
}

template <int D>
bool SortedGridN<D>::block_occupied(const CellN<D>& cell) const noexcept {
  if (block_bits_.empty()) return true;
  std::uint64_t index = 0;
  for (int k = D - 1; k >= 0; --k) {
    index = index * static_cast<std::uint64_t>(block_dims_[k]) + static_cast<std::uint64_t>(cell[k] >> block_shift_);
  }
  return (block_bits_[index >> 6] >> (index & 63)) & 1u;
}

template <int D>
void SortedGridN<D>::fill_counting(std::span<const AabbN<D>> boxes, std::uint64_t total_cells) {
  // Count the entries of each cell, turn counts into first positions, then write each entry at
  // its cell's next position: boxes in ascending id order, so ids ascend within a cell. (The
  // grid and the arrays in locals: the stores of counts and entries may alias the members.)
  offsets_.assign(total_cells + 1, 0);
  const GridMapping<D> grid = grid_;
  std::uint32_t* const offsets = offsets_.data();
  for (const CellRange& r : ranges_) {
    for_each_cell_of_range<D>(r.lo, r.hi, [&](const CellN<D>& cell, std::uint32_t) {
      ++offsets[grid.linear_index(cell) + 1];
    });
  }
  // Prefix sums into first positions, and the runs (occupied cells) at the same time.
  runs_.clear();
  std::uint32_t sum = 0;
  for (std::uint64_t c = 0; c < total_cells; ++c) {
    const std::uint32_t count = offsets[c + 1];
    if (count != 0) runs_.push_back({c, static_cast<int>(sum)});
    sum += count;
    offsets[c + 1] = sum;
  }
  runs_.push_back({~std::uint64_t{0}, static_cast<int>(entry_total_)});
  entries_.resize(entry_total_);
  CellEntry* const entries = entries_.data();
  for (const CellRange& r : ranges_) {
    const AabbN<D> box = boxes[r.id];
    const int id = r.id;
    for_each_cell_of_range<D>(r.lo, r.hi, [&](const CellN<D>& cell, std::uint32_t first_axes) {
      entries[offsets[grid.linear_index(cell)]++] = {box, id, first_axes};
    });
  }
  // offsets_[c] is now the end of cell c, the start of cell c + 1.
}

template <int D>
template <class Record, class Split>
void SortedGridN<D>::sort_and_gather(std::vector<Record>& keys, std::vector<Record>& scratch,
                                     int first_bit, int key_bits,
                                     std::span<const AabbN<D>> boxes, Split&& split) {
  radix_sort_by_key(keys, scratch, first_bit, key_bits);
  entries_.resize(keys.size());
  runs_.clear();
  std::uint64_t previous = ~std::uint64_t{0};
  const std::size_t count = keys.size();
  for (std::size_t e = 0; e < count; ++e) {
    const auto [cell_key, id, first_axes] = split(keys[e]);
    entries_[e] = {boxes[id], id, first_axes};
    if (cell_key != previous) {
      runs_.push_back({cell_key, static_cast<int>(e)});
      previous = cell_key;
    }
  }
  runs_.push_back({~std::uint64_t{0}, static_cast<int>(keys.size())});
}

template <int D>
void SortedGridN<D>::fill_radix(std::span<const AabbN<D>> boxes, std::uint64_t total_cells) {
  const int key_bits = static_cast<int>(std::bit_width(total_cells - 1));
  const int id_bits = std::max(
      1, static_cast<int>(std::bit_width(static_cast<std::uint32_t>(boxes.size()))));
  const int low_bits = D + id_bits;  // first-cell bits and id below the key
  if (key_bits + low_bits <= 64) {
    packed_.resize(entry_total_);
    std::size_t e = 0;
    for (const CellRange& r : ranges_) {
      const auto id = static_cast<std::uint64_t>(r.id);
      for_each_cell_of_range<D>(r.lo, r.hi, [&](const CellN<D>& cell, std::uint32_t first_axes) {
        packed_[e++] = {key_of(cell) << low_bits | std::uint64_t{first_axes} << id_bits | id};
      });
    }
    const std::uint64_t id_mask = (std::uint64_t{1} << id_bits) - 1;
    sort_and_gather(packed_, packed_scratch_, low_bits, key_bits, boxes, [&](const PackedKey& k) {
      return std::tuple{k.key >> low_bits, static_cast<int>(k.key & id_mask),
                        static_cast<std::uint32_t>(k.key >> id_bits) & kAllAxes<D>};
    });
  } else {
    wide_.resize(entry_total_);
    std::size_t e = 0;
    for (const CellRange& r : ranges_) {
      const auto id = static_cast<std::uint32_t>(r.id);
      for_each_cell_of_range<D>(r.lo, r.hi, [&](const CellN<D>& cell, std::uint32_t first_axes) {
        wide_[e++] = {key_of(cell), id, first_axes};
      });
    }
    sort_and_gather(wide_, wide_scratch_, 0, key_bits, boxes, [](const WideKey& k) {
      return std::tuple{k.key, static_cast<int>(k.id), k.first_axes};
    });
  }
}

template <int D>
int SortedGridN<D>::find_run(std::uint64_t key) const noexcept {
  if (runs_.size() < 2) return -1;
  const auto last = runs_.end() - 1;  // the sentinel is not a cell
  const auto it = std::lower_bound(runs_.begin(), last, key,
                                   [](const Run& r, std::uint64_t k) { return r.key < k; });
  return it != last && it->key == key ? static_cast<int>(it - runs_.begin()) : -1;
}

template <int D>
std::span<const typename SortedGridN<D>::CellEntry> SortedGridN<D>::entries_of(
    std::uint64_t key) const noexcept {
  if (dense_) {
    // offsets_[c] is the end of cell c's entries (fill_counting), and the start of c + 1's.
    const std::uint32_t begin = key == 0 ? 0 : offsets_[key - 1];
    return {entries_.data() + begin, static_cast<std::size_t>(offsets_[key] - begin)};
  }
  const int r = find_run(key);
  if (r < 0) return {};
  return run_entries(r);
}

template <int D>
std::span<const typename SortedGridN<D>::CellEntry> SortedGridN<D>::cell_entries(
    const CellN<D>& cell) const noexcept {
  if (cell_count() <= 0) return {};
  for (int k = 0; k < D; ++k) {
    if (cell[k] < 0 || cell[k] >= grid_.dims[k]) return {};  // no cell of this grid
  }
  if (!block_occupied(cell)) return {};  // (a sparse grid's empty block: no binary search)
  return entries_of(grid_.linear_index(cell));
}

template <int D>
void SortedGridN<D>::find_pairs(PairList& pairs) const {
  pairs.clear();
  append_pairs(pairs);
}

template <int D>
void SortedGridN<D>::append_pairs(PairList& pairs) const {
  append_cell_range_pairs(pairs, 0, cell_count());
  detail::oversized_pairs<D>(oversized_, is_oversized_, boxes_, pairs);
}

template <int D>
void SortedGridN<D>::append_cell_range_pairs(PairList& pairs, int first, int last) const {
  for (int r = first; r < last; ++r) append_cell_pairs<D>(run_entries(r), pairs);
}

template <int D>
void SortedGridN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  if (!detail::oversized_query<D>(oversized_, boxes_, box, callback)) return;
  if (cell_count() <= 0 || !overlap(box, grid_.bounds)) return;
  const CellN<D> lo = grid_.cell_of(box.min);
  const CellN<D> hi = grid_.cell_of(box.max);
  const auto visit_cell = [&](std::uint64_t key, std::span<const CellEntry> entries) {
    for (const CellEntry& entry : entries) {
      // Reported only by the cell holding the min corner of the intersection: once.
      if (overlap(box, entry.box) && grid_.linear_index(grid_.owner_cell(box, entry.box)) == key &&
          !callback(entry.id)) {
        return false;
      }
    }
    return true;
  };
  double range = 1.0;
  for (int k = 0; k < D; ++k) range *= static_cast<double>(hi[k] - lo[k] + 1);
  if (range > static_cast<double>(cell_count())) {
    // Wider than the occupied cells: scan those. A cell is in the range when the owner rule can
    // pick it, which visit_run checks entry by entry.
    for (int r = 0; r < cell_count(); ++r) {
      if (!visit_cell(runs_[r].key, run_entries(r))) return;
    }
    return;
  }
  bool inverted = false;  // a box with min above max on some axis (not a valid box)
  for (int k = 0; k < D; ++k) inverted |= hi[k] < lo[k];
  if (inverted) {
    for_each_cell<D>(lo, hi, [&](const CellN<D>& cell) {
      const std::uint64_t key = grid_.linear_index(cell);
      return visit_cell(key, entries_of(key));
    });
    return;
  }
  // Row by row along x, whose cells have consecutive keys. An entry is reported by the cell
  // holding the min corner of the intersection (the owner rule above): along axis k that is
  // the query's first cell lo[k] or the entry's own first cell (its first_axes bit k), since
  // cell_of is monotone; so a cell needs bit k of an entry for each axis where it is past
  // lo[k], and no cell of an entry needs computing. Same entries, same order as cell by cell.
  const auto visit_span = [&](const CellEntry* first, const CellEntry* last, std::uint32_t need) {
    for (; first != last; ++first) {
      if ((first->first_axes & need) == need && overlap(box, first->box) && !callback(first->id)) return false;
    }
    return true;
  };
  const auto row_key_count = static_cast<std::uint64_t>(hi[0] - lo[0]);  // cells after the first
  CellN<D> row_hi = hi;
  row_hi[0] = lo[0];
  std::size_t cursor = 0;  // sparse: rows ascend in key, so each search starts where the last ended
  for_each_cell<D>(lo, row_hi, [&](const CellN<D>& row) {
    std::uint32_t need = 0;
    for (int k = 1; k < D; ++k) need |= row[k] != lo[k] ? 1u << k : 0u;
    const std::uint64_t key_lo = grid_.linear_index(row);
    const std::uint64_t key_hi = key_lo + row_key_count;
    if (dense_) {
      // offsets_[c] is the end of cell c's entries: the row's cells are one span of entries.
      const CellEntry* base = entries_.data();
      const std::uint32_t begin = key_lo == 0 ? 0 : offsets_[key_lo - 1];
      return visit_span(base + begin, base + offsets_[key_lo], need) &&
             visit_span(base + offsets_[key_lo], base + offsets_[key_hi], need | 1u);
    }
    const auto last = runs_.end() - 1;  // the sentinel is not a cell
    auto it = std::lower_bound(runs_.begin() + static_cast<std::ptrdiff_t>(cursor), last, key_lo,
                               [](const Run& r, std::uint64_t k) { return r.key < k; });
    for (; it != last && it->key <= key_hi; ++it) {
      const CellEntry* base = entries_.data();
      if (!visit_span(base + it->begin, base + (it + 1)->begin, it->key == key_lo ? need : need | 1u)) return false;
    }
    cursor = static_cast<std::size_t>(it - runs_.begin());
    return true;
  });
}

template <int D>
void SortedGridN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  for (const int o : oversized_) {
    if (contains(boxes_[o], point) && !callback(o)) return;
  }
  if (!contains(grid_.bounds, point)) return;
  for (const CellEntry& entry : cell_entries(grid_.cell_of(point))) {
    if (contains(entry.box, point) && !callback(entry.id)) return;
  }
}

template <int D>
void SortedGridN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  ray_cast(ray, SlabRayN<D>(ray), callback);
}

template <int D>
void SortedGridN<D>::ray_cast(const RayN<D>& ray, const SlabRayN<D>& slab, RayCallback callback,
                              float clip) const {
  float limit = detail::oversized_ray_cast<D>(oversized_, boxes_, slab, clip, callback);
  if (limit <= 0.0f || cell_count() <= 0) return;
  const RayGridEntry<D> start = ray_grid_entry(grid_, ray, slab, limit);
  if (walk_length(grid_, ray, start, limit) * kWalkedCellCost > static_cast<double>(entries_.size())) {
    // A walk dearer than testing every entry (a grid widened for far-apart boxes, or a sparse
    // level of a hierarchical grid): each binned box once, at the entry of its min-corner
    // cell, in cell order, instead.
    for (const CellEntry& entry : entries_) {
      if (limit <= 0.0f) return;
      if (entry.first_axes != kAllAxes<D> || slab.fraction(entry.box, limit) < 0.0f) continue;
      const float r = callback(entry.id, limit);
      if (r < limit) limit = r;
    }
    return;
  }
  // As in HashGrid: a box is tested in the first cell of the walk inside its cell range.
  bool first = true;
  CellN<D> previous{0};
  walk_cells(grid_, ray, start, limit, [&](const CellN<D>& cell, float max_fraction) {
    const std::span<const CellEntry> entries = cell_entries(cell);
    // The box test first (four at a time): most entries of a crowded cell miss the ray, and
    // the test of the previous cell (two cell_of a box) is then made only for those it meets.
    max_fraction = for_each_touched<D>(
        slab, entries.size(), max_fraction, [&](std::size_t e) -> const AabbN<D>& { return entries[e].box; },
        [&](std::size_t e, float fraction) {
          const CellEntry& entry = entries[e];
          if (!first && cell_in_range<D>(previous, grid_.cell_of(entry.box.min), grid_.cell_of(entry.box.max))) {
            return fraction;
          }
          return callback(entry.id, fraction);
        });
    first = false;
    previous = cell;
    return max_fraction;
  });
}

template <int D>
std::size_t SortedGridN<D>::memory_bytes() const noexcept {
  return boxes_.capacity() * sizeof(AabbN<D>) + ranges_.capacity() * sizeof(CellRange) +
         offsets_.capacity() * sizeof(std::uint32_t) +
         (packed_.capacity() + packed_scratch_.capacity()) * sizeof(PackedKey) +
         (wide_.capacity() + wide_scratch_.capacity()) * sizeof(WideKey) +
         entries_.capacity() * sizeof(CellEntry) + runs_.capacity() * sizeof(Run) +
         oversized_.capacity() * sizeof(int) + is_oversized_.capacity() +
         block_bits_.capacity() * sizeof(std::uint64_t) +
         scratch_.capacity() * sizeof(float);
}

template class SortedGridN<2>;
template class SortedGridN<3>;
static_assert(BroadPhase<SortedGridN<2>, 2> && BroadPhase<SortedGridN<3>, 3>);

}  // namespace collide
