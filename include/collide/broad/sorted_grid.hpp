#pragma once
/// @file
/// A uniform grid for large worlds: no hash table and no per-cell allocation, only arrays
/// sorted each frame.
///
/// Every (cell, box) entry gets the cell's linear index as a key; one LSD radix sort over the
/// key bits actually in use (11 bits per pass) puts the boxes of each cell next to each other,
/// ids ascending. The boxes are copied into that order, so finding pairs reads memory
/// sequentially; a cell is found by binary search over the runs of equal keys. Cells are
/// counted from the world's min corner, and make_grid_mapping widens the cells when the world
/// would need more than 2^62 of them, so positions 1e6 from the origin (and much further) work.
/// Pairs are reported by the one cell holding the min corner of their intersection, as in
/// HashGrid. (Sorting cell keys each frame: Le Grand, "Broad-Phase Collision Detection with
/// CUDA", GPU Gems 3, 32, 2007.)
///
/// Memory per object: its box (8*D bytes) plus, per covered cell, a 16-byte sort entry, its
/// scratch copy and an (8*D + 4)-byte sorted box; plus 16 bytes per occupied cell.

#include <collide/broad/broad_phase.hpp>
#include <collide/broad/grid_mapping.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace collide {

/// Radix-sorted uniform grid over boxes in D dimensions.
template <int D>
class SortedGridN {
 public:
  struct Options {
    /// Side of a cell in world units; 0 (the default) chooses twice the median box size.
    float cell_size = 0.0f;
    /// A box covering more cells than this is kept out of the grid and tested against all.
    int max_cells_per_box = 256;
  };

  /// A box in the grid, in cell order.
  struct CellEntry {
    AabbN<D> box;
    int id;
  };

  SortedGridN() = default;
  /// Throws InvalidInput for a negative or non-finite cell size or max_cells_per_box < 1.
  explicit SortedGridN(Options options);

  /// Rebuilds the grid from the boxes. Throws InvalidInput for a non-finite box or min > max.
  void build(std::span<const AabbN<D>> boxes);
  /// Rebuilds from the moved boxes, keeping the cell size chosen at build. Throws as build.
  void update(std::span<const AabbN<D>> boxes);

  /// Builds over only the boxes listed in `ids` (validated by the caller) on a given grid, with
  /// no oversized list: a level of HierarchicalGrid. Pairs and queries then cover those ids.
  void build_subset(std::span<const AabbN<D>> boxes, std::span<const int> ids,
                    const GridMapping<D>& grid);

  /// Every overlapping pair once, i < j. Order: cells by linear index, ids ascending in a
  /// cell; oversized boxes last.
  void find_pairs(PairList& pairs) const;
  /// find_pairs without clearing `pairs` first: appends.
  void append_pairs(PairList& pairs) const;
  /// Each id whose box overlaps `box` once.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Each id whose box contains `point` once.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Each id whose box the ray meets once: oversized boxes first, then along the ray (3D-DDA).
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return count_; }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;
  [[nodiscard]] const GridMapping<D>& grid() const noexcept { return grid_; }
  [[nodiscard]] int cell_count() const noexcept { return static_cast<int>(runs_.size()) - 1; }
  [[nodiscard]] int oversized_count() const noexcept {
    return static_cast<int>(oversized_.size());
  }
  /// The boxes in `cell`, ids ascending; empty when the cell holds none.
  [[nodiscard]] std::span<const CellEntry> cell_entries(const CellN<D>& cell) const noexcept;

 private:
  // Sort records: the cell key and the id packed in one word when they fit in 64 bits (half
  // the memory traffic of the wide record), else side by side.
  struct PackedKey {
    std::uint64_t key;  // cell key << id_bits_ | id
  };
  struct WideKey {
    std::uint64_t key;
    std::uint32_t id;
    std::uint32_t unused;
  };
  struct Run {
    std::uint64_t key;
    int begin;
  };

  template <class ForEachId>
  void fill(std::span<const AabbN<D>> boxes, ForEachId&& for_each_id);
  template <class Emit>
  void emit_cells(const CellN<D>& lo, const CellN<D>& hi, Emit&& emit) const;
  template <class Record, class Split>
  void sort_and_gather(std::vector<Record>& keys, std::vector<Record>& scratch, int first_bit,
                       int key_bits, std::span<const AabbN<D>> boxes, Split&& split);
  [[nodiscard]] int find_run(std::uint64_t key) const noexcept;

  Options options_{};
  GridMapping<D> grid_{};
  int count_ = 0;                     // objects in the grid
  std::vector<AabbN<D>> boxes_;       // copy of the input (oversized tests and ray casts)
  float chosen_cell_size_ = 0.0f;     // from the data at build; kept by update
  std::vector<PackedKey> packed_;     // (cell key, id) entries, radix-sorted
  std::vector<PackedKey> packed_scratch_;
  std::vector<WideKey> wide_;
  std::vector<WideKey> wide_scratch_;
  std::vector<CellEntry> entries_;    // boxes in key order
  std::vector<Run> runs_;             // first entry of each cell, plus an end sentinel
  std::vector<int> oversized_;
  std::vector<std::uint8_t> is_oversized_;
  std::vector<float> scratch_;
};

using SortedGrid = SortedGridN<2>;
using SortedGrid3 = SortedGridN<3>;

}  // namespace collide
