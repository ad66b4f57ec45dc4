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
template <class Emit>
void SortedGridN<D>::emit_cells(const CellN<D>& lo, const CellN<D>& hi, Emit&& emit) const {
  // Linear keys of the covered cells, x fastest, without re-deriving each key from scratch.
  const auto nx = static_cast<std::uint64_t>(grid_.dims[0]);
  if constexpr (D == 2) {
    for (int y = lo.y; y <= hi.y; ++y) {
      const std::uint64_t row = static_cast<std::uint64_t>(y) * nx;
      for (int x = lo.x; x <= hi.x; ++x) emit(row + static_cast<std::uint64_t>(x));
    }
  } else {
    const std::uint64_t ny = static_cast<std::uint64_t>(grid_.dims[1]);
    for (int z = lo.z; z <= hi.z; ++z) {
      for (int y = lo.y; y <= hi.y; ++y) {
        const std::uint64_t row = (static_cast<std::uint64_t>(z) * ny + static_cast<std::uint64_t>(y)) * nx;
        for (int x = lo.x; x <= hi.x; ++x) emit(row + static_cast<std::uint64_t>(x));
      }
    }
  }
}

template <int D>
template <class Record, class Split>
void SortedGridN<D>::sort_and_gather(std::vector<Record>& keys, std::vector<Record>& scratch,
                                     int first_bit, int key_bits,
                                     std::span<const AabbN<D>> boxes, Split&& split) {
  detail::radix_sort_by_key(keys, scratch, first_bit, key_bits);
  entries_.resize(keys.size());
  runs_.clear();
  std::uint64_t previous = ~std::uint64_t{0};
  const std::size_t count = keys.size();
  for (std::size_t e = 0; e < count; ++e) {
    const auto [cell_key, id] = split(keys[e]);
    entries_[e] = {boxes[id], id};
    if (cell_key != previous) {
      runs_.push_back({cell_key, static_cast<int>(e)});
      previous = cell_key;
    }
  }
  runs_.push_back({~std::uint64_t{0}, static_cast<int>(keys.size())});
}

template <int D>
template <class ForEachId>
void SortedGridN<D>::fill(std::span<const AabbN<D>> boxes, ForEachId&& for_each_id) {
  std::uint64_t total_cells = 1;  // below 2^62 (make_grid_mapping)
  for (int k = 0; k < D; ++k) total_cells *= static_cast<std::uint64_t>(grid_.dims[k]);
  const int key_bits = static_cast<int>(std::bit_width(total_cells - 1));
  const int id_bits = std::max(
      1, static_cast<int>(std::bit_width(static_cast<std::uint32_t>(boxes.size()))));
  if (key_bits + id_bits <= 64) {
    packed_.clear();
    for_each_id([&](int id, const CellN<D>& lo, const CellN<D>& hi) {
      emit_cells(lo, hi, [&](std::uint64_t key) {
        packed_.push_back({key << id_bits | static_cast<std::uint64_t>(id)});
      });
    });
    const std::uint64_t id_mask = (std::uint64_t{1} << id_bits) - 1;
    sort_and_gather(packed_, packed_scratch_, id_bits, key_bits, boxes, [&](const PackedKey& k) {
      return std::pair{k.key >> id_bits, static_cast<int>(k.key & id_mask)};
    });
  } else {
    wide_.clear();
    for_each_id([&](int id, const CellN<D>& lo, const CellN<D>& hi) {
      emit_cells(lo, hi, [&](std::uint64_t key) {
        wide_.push_back({key, static_cast<std::uint32_t>(id), 0u});
      });
    });
    sort_and_gather(wide_, wide_scratch_, 0, key_bits, boxes, [](const WideKey& k) {
      return std::pair{k.key, static_cast<int>(k.id)};
    });
  }
}

template <int D>
void SortedGridN<D>::build(std::span<const AabbN<D>> boxes) {
  validate_boxes(boxes);
  chosen_cell_size_ =
      options_.cell_size > 0.0f ? options_.cell_size : suggest_cell_size(boxes, scratch_);
  update(boxes);
}

template <int D>
void SortedGridN<D>::update(std::span<const AabbN<D>> boxes) {
  if (chosen_cell_size_ == 0.0f) {
    build(boxes);
    return;
  }
  validate_boxes(boxes);
  boxes_.assign(boxes.begin(), boxes.end());
  count_ = static_cast<int>(boxes.size());
  grid_ = make_grid_mapping(bounds_of(boxes), chosen_cell_size_);
  oversized_.clear();
  is_oversized_.assign(boxes.size(), 0);
  const double max_cells = options_.max_cells_per_box;
  fill(boxes, [&](auto&& add) {
    for (int i = 0; i < count_; ++i) {
      const CellN<D> lo = grid_.cell_of(boxes[i].min);
      const CellN<D> hi = grid_.cell_of(boxes[i].max);
      double cells = 1.0;
      for (int k = 0; k < D; ++k) cells *= static_cast<double>(hi[k] - lo[k] + 1);
      if (cells > max_cells) {
        oversized_.push_back(i);
        is_oversized_[i] = 1;
        continue;
      }
      add(i, lo, hi);
    }
  });
}

template <int D>
void SortedGridN<D>::build_subset(std::span<const AabbN<D>> boxes, std::span<const int> ids,
                                  const GridMapping<D>& grid) {
  boxes_.clear();
  count_ = static_cast<int>(ids.size());
  oversized_.clear();
  is_oversized_.clear();
  grid_ = grid;
  fill(boxes, [&](auto&& add) {
    for (const int id : ids) add(id, grid_.cell_of(boxes[id].min), grid_.cell_of(boxes[id].max));
  });
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
         (packed_.capacity() + packed_scratch_.capacity()) * sizeof(PackedKey) +
         (wide_.capacity() + wide_scratch_.capacity()) * sizeof(WideKey) +
         entries_.capacity() * sizeof(CellEntry) + runs_.capacity() * sizeof(Run) +
         oversized_.capacity() * sizeof(int) + is_oversized_.capacity() +
         scratch_.capacity() * sizeof(float);
}

template class SortedGridN<2>;
template class SortedGridN<3>;
static_assert(BroadPhase<SortedGridN<2>, 2> && BroadPhase<SortedGridN<3>, 3>);

}  // namespace collide
