#pragma once
/// @file
/// The lesson's hashed uniform grid ("A Shout-Out to Grids"), done right.
///
/// The lesson's `broad_phase` puts each box in every cell it covers and reports it against every
/// box already in those cells. Its exercise questions point at the bugs this version fixes:
///  - a pair sharing k cells was reported k times: here a pair is reported only by the cell that
///    holds the min corner of the two boxes' intersection (GridMapping::owner_cell), so each
///    pair comes out once with no global set of seen pairs;
///  - `unordered_map` instead of `unordered_multimap` kept one box per cell: here a cell owns a
///    contiguous run of ids, as many as cover it;
///  - `floor` for the max corner is right (a box touching a cell boundary must be in both
///    cells), and negative coordinates work because cells are counted from the world's min
///    corner;
///  - boxes covering very many cells are not spread over thousands of cells: above
///    Options::max_cells_per_box they go to an "oversized" list tested against every box (so do
///    boxes reaching beyond kGridCoordinateLimit, about 1.7e38, where no cell is laid);
///  - the cell size is chosen from the data (twice the median box size) when not given.
///
/// Storage: an open-addressed hash table (cell -> dense cell index, linear probing; hash of
/// Teschner et al., "Optimized Spatial Hashing for Collision Detection of Deformable Objects",
/// VMV 2003) and the ids of all cells in one array (compressed rows), rebuilt each update. No
/// allocation per frame once the vectors have grown. Memory per object: its box (8*D bytes)
/// plus about 12 bytes per covered cell entry plus the table (2 slots of 4 bytes per cell).

#include <collide/broad/broad_phase.hpp>
#include <collide/broad/grid_mapping.hpp>
#include <collide/core/large_pages.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace collide {

/// Hashed uniform grid over boxes in D dimensions.
template <int D>
class HashGridN {
 public:
  /// What the constructor takes; it rejects bad values, naming the field.
  struct Options {
    /// Side of a cell in world units; 0 (the default) chooses twice the median box size.
    /// A size too small for the world extent (over 2^30 cells per axis) is enlarged.
    float cell_size = 0.0f;
    /// A box covering more cells than this is kept out of the grid and tested against all.
    int max_cells_per_box = 256;
  };

  HashGridN() = default;
  /// Throws InvalidInput for a negative or non-finite cell size or max_cells_per_box < 1.
  explicit HashGridN(Options options);

  /// Grows the storage for `boxes` boxes covering `cell_entries` cells in all, so that later
  /// builds up to that size allocate nothing (the lesson's `grid.reserve`). Throws InvalidInput
  /// for a negative argument, naming it ("HashGrid reserve boxes: negative (-1)").
  void reserve(int boxes, int cell_entries);

  /// Rebuilds the grid from the boxes. Throws InvalidInput for a non-finite box or min > max.
  void build(std::span<const AabbN<D>> boxes);
  /// Rebuilds from the moved boxes (a uniform grid is cheap to rebuild), keeping the cell size
  /// chosen at build. Throws as build.
  void update(std::span<const AabbN<D>> boxes);

  /// Every overlapping pair once, i < j. Order: cells in order of first use, then ids
  /// ascending in a cell; oversized boxes last.
  void find_pairs(PairList& pairs) const;
  /// Each id whose box overlaps `box` once.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Each id whose box contains `point` once.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Each id whose box the ray meets once, oversized boxes first, then cell by cell along the
  /// ray (3D-DDA); clipping by the callback ends the walk early. A ray crossing more cells than
  /// are occupied (walk_length) tests the binned boxes in id order instead.
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return static_cast<int>(boxes_.size()); }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;
  /// The grid of the last build (cell size actually used, bounds).
  [[nodiscard]] const GridMapping<D>& grid() const noexcept { return grid_; }
  /// Occupied cells in the last build.
  [[nodiscard]] int cell_count() const noexcept { return static_cast<int>(cells_.size()); }
  /// Boxes kept out of the grid because they cover too many cells.
  [[nodiscard]] int oversized_count() const noexcept {
    return static_cast<int>(oversized_.size());
  }

 private:
  [[nodiscard]] int find_cell(const CellN<D>& cell) const noexcept;
  int find_or_add_cell(const CellN<D>& cell);
  void grow_table(std::size_t slots);

  Options options_{};
  GridMapping<D> grid_{};
  float chosen_cell_size_ = 0.0f;        // from the data at build; kept by update
  // The arrays of a big grid (a 3D level's millions of triangles in the world's check) on large
  // pages: built one push at a time, they took half the page faults of a 2e5-body 3D run.
  LargePageVector<AabbN<D>> boxes_;
  LargePageVector<CellN<D>> cells_;          // coordinates of each occupied cell, in order of first use
  LargePageVector<int> cell_start_;          // ids of cell c: ids_[cell_start_[c] .. cell_start_[c+1])
  LargePageVector<int> ids_;                 // ids of all cells, ascending within a cell
  LargePageVector<int> table_;               // hash slots: -1 empty, else a cell index
  LargePageVector<int> entry_cell_;          // build scratch: cell index of each (cell, id) entry
  LargePageVector<int> entry_id_;            // build scratch: id of each entry
  LargePageVector<int> cursor_;             // build scratch: fill position of each cell
  std::vector<int> oversized_;           // ids kept out of the grid, ascending
  std::vector<std::uint8_t> is_oversized_;
  std::vector<float> scratch_;
};

using HashGrid = HashGridN<2>;
using HashGrid3 = HashGridN<3>;

}  // namespace collide
