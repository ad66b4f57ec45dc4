#include <collide/broad/sorted_grid.hpp>

#include "oversized_boxes.hpp"
#include "radix_sort.hpp"

#include <collide/core/error.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

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
void SortedGridN<D>::add_entries(int id, const AabbN<D>& box) {
  for_each_cell<D>(grid_.cell_of(box.min), grid_.cell_of(box.max), [&](const CellN<D>& c) {
    keys_.push_back({grid_.linear_index(c), static_cast<std::uint32_t>(id), 0u});
    return true;
  });
}

template <int D>
void SortedGridN<D>::sort_and_gather(std::span<const AabbN<D>> boxes) {
  std::uint64_t max_key = 0;
  for (const SortKey& k : keys_) max_key = std::max(max_key, k.key);
  detail::radix_sort_by_key(keys_, keys_scratch_, static_cast<int>(std::bit_width(max_key)));

  entries_.resize(keys_.size());
  runs_.clear();
  for (std::size_t e = 0; e < keys_.size(); ++e) {
    entries_[e] = {boxes[keys_[e].id], static_cast<int>(keys_[e].id)};
    if (e == 0 || keys_[e].key != keys_[e - 1].key) {
      runs_.push_back({keys_[e].key, static_cast<int>(e)});
    }
  }
  runs_.push_back({~std::uint64_t{0}, static_cast<int>(keys_.size())});
}

template <int D>
void SortedGridN<D>::build(std::span<const AabbN<D>> boxes) {
  validate_boxes(boxes);
  boxes_.assign(boxes.begin(), boxes.end());
  count_ = static_cast<int>(boxes.size());
  const float cell =
      options_.cell_size > 0.0f ? options_.cell_size : suggest_cell_size(boxes, scratch_);
  grid_ = make_grid_mapping(bounds_of(boxes), cell);
  keys_.clear();
  oversized_.clear();
  is_oversized_.assign(boxes.size(), 0);
  const int n = static_cast<int>(boxes.size());
  for (int i = 0; i < n; ++i) {
    if (grid_.cell_count(boxes[i]) > static_cast<double>(options_.max_cells_per_box)) {
      oversized_.push_back(i);
      is_oversized_[i] = 1;
      continue;
    }
    add_entries(i, boxes[i]);
  }
  sort_and_gather(boxes);
}

template <int D>
void SortedGridN<D>::build_subset(std::span<const AabbN<D>> boxes, std::span<const int> ids,
                                  const GridMapping<D>& grid) {
  boxes_.clear();
  count_ = static_cast<int>(ids.size());
  oversized_.clear();
  is_oversized_.clear();
  grid_ = grid;
  keys_.clear();
  for (const int id : ids) add_entries(id, boxes[id]);
  sort_and_gather(boxes);
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
std::span<const typename SortedGridN<D>::CellEntry> SortedGridN<D>::cell_entries(
    const CellN<D>& cell) const noexcept {
  const int r = find_run(grid_.linear_index(cell));
  if (r < 0) return {};
  return {entries_.data() + runs_[r].begin,
          static_cast<std::size_t>(runs_[r + 1].begin - runs_[r].begin)};
}

template <int D>
void SortedGridN<D>::find_pairs(PairList& pairs) const {
  pairs.clear();
  append_pairs(pairs);
}

template <int D>
void SortedGridN<D>::append_pairs(PairList& pairs) const {
  const int cells = cell_count();
  for (int r = 0; r < cells; ++r) {
    const std::uint64_t key = runs_[r].key;
    const int end = runs_[r + 1].begin;
    for (int e = runs_[r].begin; e < end; ++e) {
      const CellEntry a = entries_[e];
      for (int f = e + 1; f < end; ++f) {
        const CellEntry& b = entries_[f];
        if (overlap(a.box, b.box) && grid_.linear_index(grid_.owner_cell(a.box, b.box)) == key) {
          pairs.emplace_back(a.id, b.id);
        }
      }
    }
  }
  detail::oversized_pairs<D>(oversized_, is_oversized_, boxes_, pairs);
}

template <int D>
void SortedGridN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  if (!detail::oversized_query<D>(oversized_, boxes_, box, callback)) return;
  if (cell_count() <= 0 || !overlap(box, grid_.bounds)) return;
  const CellN<D> lo = grid_.cell_of(box.min);
  const CellN<D> hi = grid_.cell_of(box.max);
  const auto visit_run = [&](int r) {
    for (int e = runs_[r].begin; e < runs_[r + 1].begin; ++e) {
      const CellEntry& entry = entries_[e];
      // Reported only by the cell holding the min corner of the intersection: once.
      if (overlap(box, entry.box) &&
          grid_.linear_index(grid_.owner_cell(box, entry.box)) == runs_[r].key &&
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
      if (!visit_run(r)) return;
    }
    return;
  }
  for_each_cell<D>(lo, hi, [&](const CellN<D>& cell) {
    const int r = find_run(grid_.linear_index(cell));
    return r < 0 || visit_run(r);
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
  const float limit = detail::oversized_ray_cast<D>(oversized_, boxes_, ray, 1.0f, callback);
  if (limit <= 0.0f || cell_count() <= 0) return;
  // As in HashGrid: a box is tested in the first cell of the walk inside its cell range.
  bool first = true;
  CellN<D> previous{0};
  walk_cells(grid_, ray, limit, [&](const CellN<D>& cell, float max_fraction) {
    for (const CellEntry& entry : cell_entries(cell)) {
      if (max_fraction <= 0.0f) break;
      if (!first && cell_in_range<D>(previous, grid_.cell_of(entry.box.min),
                                     grid_.cell_of(entry.box.max))) {
        continue;
      }
      if (ray_box_fraction(ray, entry.box, max_fraction) < 0.0f) continue;
      const float r = callback(entry.id, max_fraction);
      if (r < max_fraction) max_fraction = r;
    }
    first = false;
    previous = cell;
    return max_fraction;
  });
}

template <int D>
std::size_t SortedGridN<D>::memory_bytes() const noexcept {
  return boxes_.capacity() * sizeof(AabbN<D>) +
         (keys_.capacity() + keys_scratch_.capacity()) * sizeof(SortKey) +
         entries_.capacity() * sizeof(CellEntry) + runs_.capacity() * sizeof(Run) +
         oversized_.capacity() * sizeof(int) + is_oversized_.capacity() +
         scratch_.capacity() * sizeof(float);
}

template class SortedGridN<2>;
template class SortedGridN<3>;
static_assert(BroadPhase<SortedGridN<2>, 2> && BroadPhase<SortedGridN<3>, 3>);

}  // namespace collide
