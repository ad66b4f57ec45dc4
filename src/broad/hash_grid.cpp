#include <collide/broad/hash_grid.hpp>

#include "oversized_boxes.hpp"

#include <collide/core/error.hpp>

#include <bit>
#include <cmath>
#include <string>

namespace collide {

namespace {

/// Spatial hash of a cell: coordinates times large primes, xor-ed (Teschner et al. 2003).
template <int D>
std::uint32_t hash_cell(const CellN<D>& c) noexcept {
  constexpr std::uint32_t kPrimes[3] = {73856093u, 19349663u, 83492791u};
  std::uint32_t h = 0;
  for (int k = 0; k < D; ++k) h ^= static_cast<std::uint32_t>(c[k]) * kPrimes[k];
  // Mix the high bits down: the table index uses the low bits.
  h ^= h >> 16;
  h *= 0x45d9f3bu;
  h ^= h >> 16;
  return h;
}

}  // namespace

template <int D>
HashGridN<D>::HashGridN(Options options) : options_(options) {
  if (!std::isfinite(options.cell_size) || options.cell_size < 0.0f) {
    throw InvalidInput("HashGrid options cell_size: negative or not finite");
  }
  if (options.max_cells_per_box < 1) {
    throw InvalidInput("HashGrid options max_cells_per_box: below 1");
  }
}

template <int D>
void HashGridN<D>::reserve(int boxes, int cell_entries) {
  // A negative int would become a huge size_t: std::length_error or bad_alloc, naming nothing.
  if (boxes < 0) throw InvalidInput("HashGrid reserve boxes: negative (" + std::to_string(boxes) + ")");
  if (cell_entries < 0) {
    throw InvalidInput("HashGrid reserve cell_entries: negative (" + std::to_string(cell_entries) + ")");
  }
  const auto box_count = static_cast<std::size_t>(boxes);
  const auto entries = static_cast<std::size_t>(cell_entries);
  boxes_.reserve(box_count);
  is_oversized_.reserve(box_count);
  scratch_.reserve(box_count);
  entry_cell_.reserve(entries);
  entry_id_.reserve(entries);
  ids_.reserve(entries);
  cells_.reserve(entries);
  cursor_.reserve(entries);
  cell_start_.reserve(entries + 1);
  table_.reserve(std::bit_ceil(2 * entries + 2));  // in size_t: 2 * INT_MAX does not overflow
}

template <int D>
void HashGridN<D>::grow_table(std::size_t slots) {
  table_.assign(slots, -1);
  const std::size_t mask = slots - 1;
  for (int c = 0; c < static_cast<int>(cells_.size()); ++c) {
    std::size_t s = hash_cell<D>(cells_[c]) & mask;
    while (table_[s] >= 0) s = (s + 1) & mask;
    table_[s] = c;
  }
}

template <int D>
int HashGridN<D>::find_cell(const CellN<D>& cell) const noexcept {
  if (table_.empty()) return -1;
  const std::size_t mask = table_.size() - 1;
  for (std::size_t s = hash_cell<D>(cell) & mask;; s = (s + 1) & mask) {
    const int c = table_[s];
    if (c < 0) return -1;
    if (cells_[c] == cell) return c;
  }
}

template <int D>
int HashGridN<D>::find_or_add_cell(const CellN<D>& cell) {
  // Keep the table at most half full: short probe sequences.
  if (2 * (cells_.size() + 1) > table_.size()) grow_table(std::max<std::size_t>(64, 2 * table_.size()));
  const std::size_t mask = table_.size() - 1;
  for (std::size_t s = hash_cell<D>(cell) & mask;; s = (s + 1) & mask) {
    const int c = table_[s];
    if (c < 0) {
      table_[s] = static_cast<int>(cells_.size());
      cells_.push_back(cell);
      return table_[s];
    }
    if (cells_[c] == cell) return c;
  }
}

template <int D>
void HashGridN<D>::build(std::span<const AabbN<D>> boxes) {
  validate_boxes(boxes);
  chosen_cell_size_ =
      options_.cell_size > 0.0f ? options_.cell_size : suggest_cell_size(boxes, scratch_);
  update(boxes);
}

template <int D>
void HashGridN<D>::update(std::span<const AabbN<D>> boxes) {
  if (chosen_cell_size_ == 0.0f) {
    build(boxes);
    return;
  }
  validate_boxes(boxes);
  boxes_.assign(boxes.begin(), boxes.end());
  grid_ = make_grid_mapping(bounds_of(boxes), chosen_cell_size_);

  cells_.clear();
  entry_cell_.clear();
  entry_id_.clear();
  oversized_.clear();
  is_oversized_.assign(boxes.size(), 0);
  // Start with a table sized for about one cell per box; it doubles when half full.
  table_.assign(std::bit_ceil(std::max<std::size_t>(64, 2 * boxes.size())), -1);

  const int n = size();
  // Two copies of the loop, so that an ordinary world's (the whole world inside the grid) has
  // no test for boxes beyond kGridCoordinateLimit, which are kept out of the cells too: queries
  // and ray walks stop at the grid's bounds.
  const auto bin = [&]<bool kPartial>() {
    for (int i = 0; i < n; ++i) {
      const AabbN<D>& b = boxes_[i];
      bool out = grid_.cell_count(b) > static_cast<double>(options_.max_cells_per_box);
      if constexpr (kPartial) out = out || !contains(grid_.bounds, b);
      if (out) {
        oversized_.push_back(i);
        is_oversized_[i] = 1;
        continue;
      }
      for_each_cell<D>(grid_.cell_of(b.min), grid_.cell_of(b.max), [&](const CellN<D>& c) {
        entry_cell_.push_back(find_or_add_cell(c));
        entry_id_.push_back(i);
        return true;
      });
    }
  };
  if (grid_.partial) {
    bin.template operator()<true>();
  } else {
    bin.template operator()<false>();
  }

  // Counting sort of the entries by cell: each cell's ids contiguous, ascending.
  const std::size_t cell_total = cells_.size();
  cell_start_.assign(cell_total + 1, 0);
  for (const int c : entry_cell_) ++cell_start_[c + 1];
  for (std::size_t c = 0; c < cell_total; ++c) cell_start_[c + 1] += cell_start_[c];
  ids_.resize(entry_id_.size());
  cursor_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t e = 0; e < entry_id_.size(); ++e) ids_[cursor_[entry_cell_[e]]++] = entry_id_[e];
}

template <int D>
void HashGridN<D>::find_pairs(PairList& pairs) const {
  pairs.clear();
  const int cell_total = cell_count();
  for (int c = 0; c < cell_total; ++c) {
    const CellN<D> cell = cells_[c];
    const int end = cell_start_[c + 1];
    for (int e = cell_start_[c]; e < end; ++e) {
      const int a = ids_[e];
      const AabbN<D> box_a = boxes_[a];
      for (int f = e + 1; f < end; ++f) {
        const int b = ids_[f];
        const AabbN<D>& box_b = boxes_[b];
        if (overlap(box_a, box_b) && grid_.owner_cell(box_a, box_b) == cell) {
          pairs.emplace_back(a, b);
        }
      }
    }
  }
  detail::oversized_pairs<D>(oversized_, is_oversized_, boxes_, pairs);
}

template <int D>
void HashGridN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  if (!detail::oversized_query<D>(oversized_, boxes_, box, callback)) return;
  if (!overlap(box, grid_.bounds)) return;
  const CellN<D> lo = grid_.cell_of(box.min);
  const CellN<D> hi = grid_.cell_of(box.max);
  // A box is reported only by the cell holding the min corner of its intersection with the
  // query, as in find_pairs: once, with no set of seen ids.
  const auto visit = [&](int c) {
    for (int e = cell_start_[c]; e < cell_start_[c + 1]; ++e) {
      const int id = ids_[e];
      if (overlap(box, boxes_[id]) && grid_.owner_cell(box, boxes_[id]) == cells_[c] &&
          !callback(id)) {
        return false;
      }
    }
    return true;
  };
  double range = 1.0;
  for (int k = 0; k < D; ++k) range *= static_cast<double>(hi[k] - lo[k] + 1);
  if (range > static_cast<double>(cells_.size())) {
    // A query wider than the occupied cells: walk the occupied cells instead of the range.
    for (int c = 0; c < cell_count(); ++c) {
      if (cell_in_range<D>(cells_[c], lo, hi) && !visit(c)) return;
    }
    return;
  }
  for_each_cell<D>(lo, hi, [&](const CellN<D>& cell) {
    const int c = find_cell(cell);
    return c < 0 || visit(c);
  });
}

template <int D>
void HashGridN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  for (const int o : oversized_) {
    if (contains(boxes_[o], point) && !callback(o)) return;
  }
  if (!contains(grid_.bounds, point)) return;
  const int c = find_cell(grid_.cell_of(point));
  if (c < 0) return;
  for (int e = cell_start_[c]; e < cell_start_[c + 1]; ++e) {
    if (contains(boxes_[ids_[e]], point) && !callback(ids_[e])) return;
  }
}

template <int D>
void HashGridN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  const SlabRayN<D> slab(ray);  // (one for every box test, the grid's bounds among them)
  float limit = detail::oversized_ray_cast<D>(oversized_, boxes_, slab, 1.0f, callback);
  if (limit <= 0.0f || cells_.empty()) return;
  const RayGridEntry<D> start = ray_grid_entry(grid_, ray, slab, limit);
  if (walk_length(grid_, ray, start, limit) > static_cast<double>(cells_.size())) {
    // A walk longer than the occupied cells (a grid widened for far-apart boxes): each binned
    // box once, in id order, instead.
    const int n = size();
    for (int id = 0; id < n && limit > 0.0f; ++id) {
      if (is_oversized_[static_cast<std::size_t>(id)] || slab.fraction(boxes_[id], limit) < 0.0f) continue;
      const float r = callback(id, limit);
      if (r < limit) limit = r;
    }
    return;
  }
  // The cells along the ray change monotonically on each axis, so the cells of the walk that
  // lie in a box's cell range are consecutive: a box is met first where the previous cell of the
  // walk was outside its range, and tested only there.
  bool first = true;
  CellN<D> previous{0};
  walk_cells(grid_, ray, start, limit, [&](const CellN<D>& cell, float max_fraction) {
    const int c = find_cell(cell);
    if (c >= 0) {
      // The box test first, four boxes at a time, then the test of the previous cell.
      const int* ids = ids_.data() + cell_start_[c];
      const auto count = static_cast<std::size_t>(cell_start_[c + 1] - cell_start_[c]);
      max_fraction = for_each_touched<D>(
          slab, count, max_fraction, [&](std::size_t e) -> const AabbN<D>& { return boxes_[ids[e]]; },
          [&](std::size_t e, float fraction) {
            const AabbN<D>& b = boxes_[ids[e]];
            if (!first && cell_in_range<D>(previous, grid_.cell_of(b.min), grid_.cell_of(b.max))) return fraction;
            return callback(ids[e], fraction);
          });
    }
    first = false;
    previous = cell;
    return max_fraction;
  });
}

template <int D>
std::size_t HashGridN<D>::memory_bytes() const noexcept {
  return boxes_.capacity() * sizeof(AabbN<D>) + cells_.capacity() * sizeof(CellN<D>) +
         (cell_start_.capacity() + ids_.capacity() + table_.capacity() + entry_cell_.capacity() +
          entry_id_.capacity() + oversized_.capacity() + cursor_.capacity()) *
             sizeof(int) +
         is_oversized_.capacity() + scratch_.capacity() * sizeof(float);
}

template class HashGridN<2>;
template class HashGridN<3>;
static_assert(BroadPhase<HashGridN<2>, 2> && BroadPhase<HashGridN<3>, 3>);

}  // namespace collide
