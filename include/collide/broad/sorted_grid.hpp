#pragma once
/// @file
/// A uniform grid for large worlds: no hash table and no per-cell allocation, only arrays
/// rebuilt each frame.
///
/// Every (cell, box) entry gets the cell's linear index as a key, counted from the world's min
/// corner over the cells the boxes actually span. The entries are put in key order (ids
/// ascending within a cell) by a counting sort over all cells when the grid has at most
/// kDenseCellsPerBox cells per box, else by an LSD radix sort over the key bits in use (11 bits
/// per pass); either way each entry is written straight to its place with a copy of its box,
/// so finding pairs reads memory sequentially, and a cell is found from the counting sort's
/// offsets (one read) or by binary search over the runs of equal keys. make_grid_mapping widens
/// the cells when the world would need more than 2^62 of them, so positions 1e6 from the origin
/// (and much further) work. Pairs are reported by the one cell holding the min corner of their
/// intersection, as in HashGrid, read from the entries' first-cell bits (GridEntry). (Sorting
/// cell keys each frame: Le Grand, "Broad-Phase Collision Detection with CUDA", GPU Gems 3, 32,
/// 2007.)
///
/// Memory per object: per covered cell a (8*D + 8)-byte entry, plus a (8*D + 4)-byte cell range
/// per box, plus either 4 bytes per grid cell (counting sort) or two 8-byte sort records per
/// entry (radix sort); plus 16 bytes per occupied cell. The boxes are copied only when some are
/// oversized.

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
  /// What the constructor takes; it rejects bad values, naming the field.
  struct Options {
    /// Side of a cell in world units; 0 (the default) chooses twice the median box size.
    float cell_size = 0.0f;
    /// A box covering more cells than this is kept out of the grid and tested against all (as
    /// is a box reaching beyond kGridCoordinateLimit, about 1.7e38, where no cell is laid).
    int max_cells_per_box = 256;
  };

  /// A box in the grid, in cell order (see GridEntry).
  using CellEntry = GridEntry<D>;

  /// Most grid cells per binned box for which the entries are put in order by a counting sort
  /// over every cell (one pass, an array of 4 bytes per cell); sparser grids use a radix sort.
  static constexpr std::uint64_t kDenseCellsPerBox = 4;
  /// Sparse grids keep a bitmap of occupied blocks (2^k cells a side, k >= kMinBlockShift) in
  /// at most this many bits per binned box, so that a ray's walk passes empty cells without a
  /// binary search over the runs.
  static constexpr std::uint64_t kBlockBitsPerBox = 64;
  static constexpr int kMinBlockShift = 0;
  /// A ray cast tests every entry instead of walking the cells when the walk would visit more
  /// than entries / kWalkedCellCost cells (a cell of the walk costs about as much as this many
  /// entry tests).
  static constexpr double kWalkedCellCost = 4.0;

  SortedGridN() = default;
  /// Throws InvalidInput for a negative or non-finite cell size or max_cells_per_box < 1.
  explicit SortedGridN(Options options);

  /// Rebuilds the grid from the boxes. Throws InvalidInput for a non-finite box or min > max.
  void build(std::span<const AabbN<D>> boxes);
  /// Rebuilds from the moved boxes, keeping the cell size chosen at build. Throws as build.
  void update(std::span<const AabbN<D>> boxes);

  /// Builds over only the boxes listed in `ids` (ascending, validated by the caller, inside
  /// grid.bounds) on a given grid, with no oversized list: a level of HierarchicalGrid. Pairs
  /// and queries then cover those ids.
  void build_subset(std::span<const AabbN<D>> boxes, std::span<const int> ids,
                    const GridMapping<D>& grid);

  /// Every overlapping pair once, i < j. Order: cells by linear index, ids ascending in a
  /// cell; oversized boxes last.
  void find_pairs(PairList& pairs) const;
  /// find_pairs without clearing `pairs` first: appends.
  void append_pairs(PairList& pairs) const;
  /// The pairs found in occupied cells [first, last) (0 <= first <= last <= cell_count(), in
  /// cell order; oversized boxes not included), appended: a share of find_pairs for one worker.
  void append_cell_range_pairs(PairList& pairs, int first, int last) const;
  /// Each id whose box overlaps `box` once.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Each id whose box contains `point` once.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Each id whose box the ray meets once: oversized boxes first, then along the ray (3D-DDA);
  /// a ray crossing more cells than are occupied (walk_length) tests the binned boxes in cell
  /// order instead.
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;
  /// ray_cast with `slab`, the same ray prepared for box tests (SlabRayN(ray)), made once by a
  /// caller that casts it through several grids (a hierarchical grid's levels): its three
  /// divisions are not made again for each. `clip` (a fraction in [0, 1]) clips the ray from the
  /// start: a box met only beyond it is not given (a caller whose earlier grids clipped it).
  void ray_cast(const RayN<D>& ray, const SlabRayN<D>& slab, RayCallback callback,
                float clip = 1.0f) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return count_; }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;
  /// The grid of the last build or update: the cell size actually used (the chosen one, or
  /// wider when the world would need more than 2^62 cells) and the bounds cells count from.
  [[nodiscard]] const GridMapping<D>& grid() const noexcept { return grid_; }
  /// Cells holding at least one box after the last build or update; 0 before the first.
  [[nodiscard]] int cell_count() const noexcept {
    return runs_.empty() ? 0 : static_cast<int>(runs_.size()) - 1;  // runs_ ends in a sentinel
  }
  /// Boxes kept out of the cells in the last build or update, because they cover more than
  /// Options::max_cells_per_box cells; each is tested against every box.
  [[nodiscard]] int oversized_count() const noexcept {
    return static_cast<int>(oversized_.size());
  }
  /// The boxes in `cell`, ids ascending; empty when the cell holds none.
  [[nodiscard]] std::span<const CellEntry> cell_entries(const CellN<D>& cell) const noexcept;

 private:
  // Sort records: the cell key, the first-cell bits and the id packed in one word when they fit
  // in 64 bits (half the memory traffic of the wide record), else side by side.
  struct PackedKey {
    std::uint64_t key;  // cell key << (D + id_bits) | first_axes << id_bits | id
  };
  struct WideKey {
    std::uint64_t key;
    std::uint32_t id;
    std::uint32_t first_axes;
  };
  struct Run {
    std::uint64_t key;
    int begin;
  };
  // The cells a binned box covers.
  struct CellRange {
    CellN<D> lo;
    CellN<D> hi;
    int id;
  };

  void rebuild(std::span<const AabbN<D>> boxes, const AabbN<D>& bounds);
  void fill(std::span<const AabbN<D>> boxes);
  void fill_counting(std::span<const AabbN<D>> boxes, std::uint64_t total_cells);
  void fill_radix(std::span<const AabbN<D>> boxes, std::uint64_t total_cells);
  template <class Record, class Split>
  void sort_and_gather(std::vector<Record>& keys, std::vector<Record>& scratch, int first_bit,
                       int key_bits, std::span<const AabbN<D>> boxes, Split&& split);
  [[nodiscard]] std::uint64_t key_of(const CellN<D>& cell) const noexcept {
    return grid_.linear_index(cell);
  }
  [[nodiscard]] int find_run(std::uint64_t key) const noexcept;
  /// The entries of run r (an occupied cell), r < cell_count().
  [[nodiscard]] std::span<const CellEntry> run_entries(int r) const noexcept {
    return {entries_.data() + runs_[r].begin, static_cast<std::size_t>(runs_[r + 1].begin - runs_[r].begin)};
  }
  /// The entries of the cell with linear index `key` (< the grid's cell total): read from the
  /// counting sort's offsets when the grid is dense, else found by binary search over the runs.
  [[nodiscard]] std::span<const CellEntry> entries_of(std::uint64_t key) const noexcept;
  /// The occupied-block bitmap of a sparse grid, from ranges_ (none for a dense grid).
  void mark_blocks();
  /// False when no binned box covers the block holding `cell` (a cell of the grid).
  [[nodiscard]] bool block_occupied(const CellN<D>& cell) const noexcept;

  Options options_{};
  GridMapping<D> grid_{};
  int count_ = 0;                     // objects in the grid
  std::vector<AabbN<D>> boxes_;       // copy of the input when some are oversized, else empty
  float chosen_cell_size_ = 0.0f;     // from the data at build; kept by update
  std::vector<CellRange> ranges_;     // cells of each binned box, ids ascending
  std::size_t entry_total_ = 0;       // sum of the cells of the binned boxes
  bool dense_ = false;                // the last fill was the counting sort: offsets_ index cells
  std::vector<std::uint32_t> offsets_;  // counting sort: end of each grid cell's entries
  std::vector<PackedKey> packed_;     // radix sort: (cell key, id) entries
  std::vector<PackedKey> packed_scratch_;
  std::vector<WideKey> wide_;
  std::vector<WideKey> wide_scratch_;
  std::vector<CellEntry> entries_;    // boxes in key order
  std::vector<Run> runs_;             // first entry of each cell, plus an end sentinel
  int block_shift_ = 0;               // a block is 2^block_shift_ cells a side
  CellN<D> block_dims_{0};            // blocks per axis
  std::vector<std::uint64_t> block_bits_;  // one bit per block, set where a box is binned; empty when dense
  std::vector<int> oversized_;
  std::vector<std::uint8_t> is_oversized_;
  std::vector<float> scratch_;
};

using SortedGrid = SortedGridN<2>;
using SortedGrid3 = SortedGridN<3>;

}  // namespace collide
