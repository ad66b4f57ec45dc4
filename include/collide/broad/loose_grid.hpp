#pragma once
/// @file
/// A uniform grid built for full rebuilds every frame: one entry per box, no hashing, no
/// comparison sort.
///
/// Each box is stored once, in the cell of its min corner ("loose" cells: a box may stick out of
/// its cell by up to one cell on every axis). Cells are at least as large as most boxes, so a
/// box whose cell range spans at most two cells per axis ("small") is binned; the rest ("big")
/// are kept in a side list. Two small boxes can overlap only when their min-corner cells are
/// neighbours (differ by at most one on every axis), so find_pairs tests each cell against
/// itself and its forward half of the 3^D - 1 neighbours: every candidate pair once, no owner
/// rule and no set of reported pairs. (Binning by one reference point with a half-neighbourhood
/// scan: Ericson, "Real-Time Collision Detection", 7.1.6 and 7.1.7; the linked-cell method of
/// molecular dynamics.)
///
/// The rebuild is a counting sort over the cells: one pass computes each box's cell key (the
/// min- and max-corner cells of four boxes at a time, transposed into SIMD lanes) and counts
/// boxes per cell, a prefix sum gives each cell its first slot, a second pass writes each
/// box's (key, id) record to its slot, ids ascending in a cell, and a last pass copies the
/// boxes in that order (sequential writes; the random accesses are 8-byte records and box
/// reads). On grids of more than 2^one_step_bits cells (a million boxes) that would be random
/// accesses to memory: the records are distributed by band (2^band_bits consecutive cells),
/// each with a copy of its box (staged, so that a band's boxes are then read in one sequential
/// sweep), 64 records and boxes at a time (whole cache lines) from per-band buffers, by
/// streaming stores (software write-combining: no read of the lines before writing them); each
/// band is then sorted on its own in cache, cell starts included, and the results written out
/// with streaming stores (build_and_find_pairs and update_and_find_pairs also keep them in a
/// window in cache, with the tail of the band before, and find the band's pairs there: the
/// pair pass then reads nothing from memory); an update on the same grid sizes the bands' regions
/// from the last call's counts, so that the key pass itself distributes the records. The
/// long passes prefetch ahead (the hardware prefetchers left them waiting on memory at a
/// million boxes). The grid is dense over the
/// boxes' bounds, with a border of empty cells so that every neighbour of an occupied cell
/// exists; when the cells from the requested size would exceed kCellsPerBox per box, the cells
/// are widened (results stay exact, only the neighbour scans grow). Keys are 32-bit. There is
/// no separate pass for the bounds: build lays the grid over the bounds of the boxes it samples
/// for the cell size, grown a little, and update keeps the grid of the last call; the key pass
/// validates each box and tests it against the grid's bounds, and a box outside (an outlier)
/// is kept with the big boxes. Only when there are more than outlier_limit of them is the grid
/// laid over the exact bounds (grown by kUpdateMargin in update); no grid reaches beyond
/// kGridCoordinateLimit (about 1.7e38), so boxes there stay outliers, however many. Clustered,
/// sparse worlds are better served by SortedGrid, mixed sizes by HierarchicalGrid (here the big
/// boxes are tested per cell range against the small ones and by a sweep along x against each
/// other).
///
/// The binned boxes are stored sorted, one array per coordinate (structure of arrays), so the
/// pair pass streams memory and tests a box against four candidates with one SIMD compare per
/// coordinate: the forward neighbourhood of a box is 2 (2D) or 5 (3D) contiguous runs of
/// entries, each usually shorter than four, so each run is one branch-free test. A box can meet
/// a box of a row above on an axis only if its own max corner reaches that row, so in 3D the
/// pair pass groups the entries (a chunk at a time) by which of y and z their boxes cross and
/// tests each group's runs only (3.6 runs per box instead of 5 on the bench world). Each run
/// tests only the comparisons its row needs (a box in a row above cannot fail min <= max on
/// that axis), and the pairs are written after each block of entries, from the entries that
/// had an overlap.
///
/// Memory per object: 2*D 4-byte coordinates, an 8-byte (key, id) record and a 4-byte key, plus
/// at most kCellsPerBox 4-byte cell starts (2 in 2D, 2.6 in 3D on the bench world); on grids
/// sorted band by band, 1/8 more records (the regions' slack), a staged box per record (8*D
/// bytes: 18 B per object in 2D, 27 in 3D with the slack) and one band's copies (records,
/// boxes and cell starts; with the combined calls, the window: a band and a tail, under 1 MiB),
/// and per band a buffer of 64 records and boxes (1.5 KiB in 2D, 2 KiB in 3D); a big box adds
/// two (8*D + 4)-byte records.

#include <collide/broad/broad_phase.hpp>
#include <collide/broad/grid_mapping.hpp>
#include <collide/core/large_pages.hpp>

#include <cstddef>
#include <cstdint>
#include <new>
#include <span>
#include <vector>

namespace collide {

/// Fraction of the boxes (by largest side) that the default LooseGrid cell is at least as large
/// as (LooseGridN::Options::cell_quantile): those span at most two cells per axis and are
/// binned; a larger cell would put more boxes in every neighbour scan.
inline constexpr float kLooseCellQuantile = 0.9f;

/// Loose uniform grid over boxes in D dimensions, rebuilt from scratch by a counting sort.
template <int D>
class LooseGridN {
 public:
  struct Options {
    /// Side of a cell in world units; 0 (the default) chooses one from the data at build: the
    /// cell_quantile quantile of the boxes' largest sides.
    float cell_size = 0.0f;
    /// With cell_size 0, the fraction of the boxes (by largest side) the cell is at least as
    /// large as, in (0, 1]. Higher: fewer big boxes (each query tests those whose x extent
    /// reaches its own) and more boxes a cell; boxes of nearly one size (the temporal broad
    /// phase's grown boxes) want nearly 1.
    float cell_quantile = kLooseCellQuantile;
    /// Grids of at most 2^one_step_bits cells (with the border) are counting-sorted in one
    /// step; larger ones band by band, bands of 2^band_bits consecutive cells, so the counting
    /// sort's random accesses stay in cache (measured on the bench worlds: one step is faster
    /// at 1e5 objects, 2-2.6e5 cells; bands at 1e6 objects, 2e6 cells). Both must be in
    /// [0, 31].
    int one_step_bits = 19;
    /// Cells per band, as a power of two (32 Ki cells: 128 KiB of cell starts). Measured per
    /// frame at 1e6 objects with update_and_find_pairs, whose band and pair pass share the
    /// cache: bands of 32 Ki cells against 64 Ki, 2D 27.3 -> 26.7, 3D 40.3 -> 39.3 ns per
    /// object (a build alone, 2D, 16.0 -> 17.4; the separate update and find_pairs unchanged).
    int band_bits = 15;
  };

  /// A big box (kept out of the cells) and its id.
  struct Entry {
    AabbN<D> box;
    int id;
  };

  /// A sample's bounds are grown by this fraction of their extent on each side to lay the grid
  /// of build: with kCellSizeSamples boxes sampled from a uniform world, a box lies beyond on a
  /// side with probability about e^-4.
  static constexpr float kSampleMargin = 4.0f / static_cast<float>(kCellSizeSamples);
  /// When update lays a new grid (too many boxes left the last one), the exact bounds are grown
  /// by this fraction of their extent, plus one cell, on each side.
  static constexpr float kUpdateMargin = 1.0f / 32.0f;
  /// On grids sorted band by band, the most boxes of one band that are sorted from their staged
  /// copies into an in-cache copy: a band with more (a crowded world) reads them straight from
  /// the span.
  static constexpr std::uint32_t kBandCopy = 1u << 16;
  /// Most grid cells per box (border included) before the cells are widened.
  static constexpr std::uint64_t kCellsPerBox = 4;
  /// Cells every grid may use regardless of the number of boxes (small worlds).
  static constexpr std::uint64_t kMinCells = 4096;

  LooseGridN() = default;
  /// Throws InvalidInput for a negative or non-finite cell size, a cell quantile outside
  /// (0, 1], or one_step_bits or band_bits outside [0, 31].
  explicit LooseGridN(Options options);

  /// Rebuilds the grid from the boxes. Throws InvalidInput for a non-finite box or min > max,
  /// leaving the grid empty (size 0) until the next build or update.
  void build(std::span<const AabbN<D>> boxes);
  /// Rebuilds from the moved boxes, keeping the cell size chosen at build and, while it still
  /// holds all but a few of the boxes, the grid of the last call (so the order of the pairs,
  /// never their set, may depend on earlier calls). Throws as build.
  void update(std::span<const AabbN<D>> boxes);

  /// build, then find_pairs into `pairs`, in one call: the same pairs in the same order, and
  /// the grid is left as build leaves it (queryable). On grids sorted band by band (more than
  /// 2^one_step_bits cells) each band's pairs are found right after the band is sorted, from
  /// copies still in cache, instead of in a second pass over the whole grid from memory; an
  /// entry whose forward neighbourhood reaches into the next band waits for it. Throws as
  /// build, leaving the grid and `pairs` empty.
  void build_and_find_pairs(std::span<const AabbN<D>> boxes, PairList& pairs);
  /// update, then find_pairs into `pairs`, in one call, as build_and_find_pairs (same pairs,
  /// same order as the two calls). Throws as update, leaving the grid and `pairs` empty.
  void update_and_find_pairs(std::span<const AabbN<D>> boxes, PairList& pairs);

  /// Every overlapping pair once, i < j. Order: small pairs by the stored entry of the first
  /// box (cells by linear index, x fastest; ids ascending in a cell; in 3D, chunks of entries
  /// by crossing class), then big boxes against small ones by big id, then big against big.
  void find_pairs(PairList& pairs) const;
  /// find_pairs without clearing `pairs` first: appends.
  void append_pairs(PairList& pairs) const;
  /// Each id whose box overlaps `box` once: big boxes first (those whose x extent can reach the
  /// box's, by a binary search of them sorted by min x), then by cell.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Each id whose box contains `point` once.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Each id whose box the ray meets once: big boxes first (those whose x extent can reach the
  /// ray's), then along the ray (3D-DDA).
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;
  /// ray_cast with `slab`, the same ray prepared for box tests (SlabRayN(ray)) by a caller that
  /// tests boxes of its own with it.
  void ray_cast(const RayN<D>& ray, const SlabRayN<D>& slab, RayCallback callback) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return count_; }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;
  /// The grid of the last build: cells (without the border) over the boxes' bounds.
  [[nodiscard]] const GridMapping<D>& grid() const noexcept { return grid_; }
  /// Boxes spanning more than two cells on some axis, kept out of the grid.
  [[nodiscard]] int big_count() const noexcept { return static_cast<int>(big_.size()); }

 private:
  // Entries past the last that a four-wide load may read: the arrays are padded with this many.
  static constexpr std::size_t kPad = 8;

  // An entry: a cell key and a box id.
  struct Record {
    std::uint32_t key;
    int id;
  };
  // Where find_pairs writes: a raw pointer into the list, grown ahead of the writes.
  struct PairSink;
  // A band and the unprocessed tail of the band before it, as find_pairs reads them, in
  // copies that stay in cache while their pairs are found (build_and_find_pairs): entry e of
  // the grid is entry e - entry0 here, cell c is cell c - cell0. Records and cell starts hold
  // the grid's keys and entries (they are written out as they are).
  struct Window {
    std::vector<float> coords;   // coordinate a of entry e at coords[a * stride + e - entry0]
    std::size_t stride = 0;
    std::vector<Record> records;
    std::vector<std::uint32_t> starts;
    std::uint32_t entry0 = 0;
    std::uint32_t cell0 = 0;
  };
  // The arrays the pair pass reads: the grid's own (bases 0) or a Window's.
  struct PairView {
    const float* coords;
    std::size_t stride;
    const Record* records;
    const std::uint32_t* starts;  // starts[c - cell_base] = the grid's starts_[c]
    std::uint32_t entry_base;     // records[e - entry_base], coords at e - entry_base
    std::uint32_t cell_base;
  };
  [[nodiscard]] PairView grid_view() const noexcept {
    return {coords_.data(), stride_, records_.data(), starts_.data(), 0, 0};
  }

  // build and update; with a sink, the small-small pairs of grids sorted by band are found
  // band by band into it (see bin).
  void build_with(std::span<const AabbN<D>> boxes, PairSink* sink);
  void update_with(std::span<const AabbN<D>> boxes, PairSink* sink);
  // The pairs still missing from the sink after build_with/update_with, and the list cut.
  void finish_pairs(PairSink& sink, PairList& pairs);
  // Empties what find_pairs and the queries read (after a throw).
  void clear() noexcept;
  // A box outside the grid (an outlier) is kept with the big ones while there are at most
  // this many; with more, the grid is laid again over the boxes' exact bounds.
  static std::size_t outlier_limit(std::size_t boxes) noexcept { return boxes / 1024 + 8; }
  // Most cells (with the border) for a grid of that many boxes.
  static std::uint64_t cell_budget(std::size_t boxes) noexcept;
  // The largest sides of a sample of the boxes into `sides`, and the sample's bounds (grown by
  // kSampleMargin of their extent when the sample is not every box). Throws as build for a
  // bad sampled box (naming the first bad box of the span).
  static AabbN<D> sample_boxes(std::span<const AabbN<D>> boxes, std::vector<float>& sides);
  // grid_, padded_ and cells_ for these bounds with the chosen cell size, widened to the budget
  // of that many boxes.
  void set_grid(const AabbN<D>& bounds, std::size_t boxes);
  // Sorts the boxes into grid_: keys, counting sort, gather. Returns false (the grid left
  // unusable) when more than outlier_limit boxes lie outside grid_.bounds, unless
  // `every_outlier` (a grid over the exact bounds, where a box is outside only beyond
  // kGridCoordinateLimit: every such box is kept with the big ones). Throws as build.
  // With a sink, on grids sorted band by band, the small-small pairs are found band by band
  // into it (from window_), and small_pairs_done_ is set.
  bool bin(std::span<const AabbN<D>> boxes, PairSink* sink = nullptr, bool every_outlier = false);
  // The key of every box (the big bucket for big boxes and outliers, which also go to big_),
  // to keys_[i] when store_keys; count(key, i) is called for each. Returns the number of
  // outliers; throws for a bad box.
  template <class Count>
  std::size_t compute_keys(std::span<const AabbN<D>> boxes, std::uint32_t big_key, bool store_keys,
                           Count&& count);
  // Sorts by cell the m records of a band at records_[from_slot...] in id order, their cells
  // in [first_cell, last_cell), to slots [first, first + m) (first <= from_slot): records,
  // cell starts and coordinates.
  // With `window`, the band's records, cell starts and coordinates are also left there (at
  // entry first - entry0, cell first_cell - cell0; room made by the caller).
  void sort_band(std::span<const AabbN<D>> boxes, std::uint32_t from_slot, std::uint32_t m,
                 std::uint32_t first, std::uint32_t first_cell, std::uint32_t last_cell,
                 Window* window = nullptr);
  // Before sorting the band of cells from first_cell, entries from `first`: window_ keeps
  // only the entries from `pending` (not yet paired) and the cells from the first of theirs
  // (or first_cell), at its front, with room for m more entries and the band's cells to
  // last_cell + 1.
  void slide_window(std::uint32_t pending, std::uint32_t first, std::uint32_t m,
                    std::uint32_t first_cell, std::uint32_t last_cell);
  // The small-small pairs of the entries [begin, end) of the grid (in 3D, begin a multiple of
  // kPairChunk and end too unless it is the last entry), read through `view`.
  template <bool kWindow>
  void append_small_range(const PairView& view, std::uint32_t begin, std::uint32_t end,
                          PairSink& sink) const;
  // Big boxes against small ones (from big_found_ when bin found them by band), then against
  // each other.
  void append_big_pairs(PairSink& sink) const;
  // For the pairs of big boxes with small ones found band by band: each big box's cell range
  // (that of for_each_run) and the big boxes whose range meets each of the `bands` bands.
  void list_big_by_band(std::uint32_t bands);
  // The big boxes listed for band b against its small boxes, cells [first_cell, last_cell),
  // in window_: their pairs to big_found_.
  void find_big_in_band(std::uint32_t b, std::uint32_t first_cell, std::uint32_t last_cell);
  // 3D: entries grouped by crossing class a chunk of this many at a time (see append_pairs).
  static constexpr std::uint32_t kPairChunk = 256;
  // On 64-byte boundaries (cache lines), for the full-line streaming stores of the
  // distribution by band, and on large pages when big (the arrays below are read at random: at
  // 1e6 objects a 4 KiB page a read missed the TLB).
  template <class T>
  using LineVector = LargePageVector<T, 64>;
  // staged_ as large as records_ (and its capacity at least records_'s).
  void stage_like_records() {
    staged_.reserve(records_.capacity());
    staged_.resize(records_.size());
  }
  // Copies box_of(e) into the coordinate arrays at entry e, for e in [first, last); with
  // kStream, by streaming stores.
  // With a window (kWindow), box_of(e) also goes to window[a * window_stride + e - first] by
  // plain stores.
  template <bool kStream, bool kWindow = false, class BoxOf>
  void gather(std::uint32_t first, std::uint32_t last, BoxOf&& box_of, float* window = nullptr,
              std::size_t window_stride = 0) noexcept;
  // The small-small pairs of the entries e in [first, last), or, when kListed, of
  // e = list[i] for i in [first, last), whose boxes all need the rows above listed in
  // kRowMask (bit r: row r of the forward neighbourhood, see append_pairs); e is an index
  // into the view's arrays (the grid's entry e + view.entry_base; with kWindow false, the
  // bases are 0).
  template <std::uint32_t kRowMask, bool kListed, bool kWindow>
  void append_small_pairs(const PairView& view, const std::uint32_t* list, std::uint32_t first,
                          std::uint32_t last, PairSink& sink) const;
  // The box stored at `slot`.
  [[nodiscard]] AabbN<D> entry_box(std::uint32_t slot) const noexcept {
    AabbN<D> box;
    for (int k = 0; k < D; ++k) {
      box.min[k] = coords_[k * stride_ + slot];
      box.max[k] = coords_[(D + k) * stride_ + slot];
    }
    return box;
  }
  // Linear index of a cell with the border: cell + 1 on every axis, x fastest.
  [[nodiscard]] std::uint32_t key_of(const CellN<D>& cell) const noexcept {
    std::uint32_t key = 0;
    for (int k = D - 1; k >= 0; --k) {
      key = key * static_cast<std::uint32_t>(padded_[k]) + static_cast<std::uint32_t>(cell[k] + 1);
    }
    return key;
  }
  // Calls visit(first, last) for the entries of the small boxes whose min-corner cell lies in
  // [lo, hi] (cells without the border, each from -1 to dims): one contiguous run per row.
  template <class Visit>
  bool for_each_run(const CellN<D>& lo, const CellN<D>& hi, Visit&& visit) const;
  // Calls report(entry) for each entry in [first, last) whose box overlaps `box`; report
  // returns false to stop (then so does this).
  template <class Report>
  bool for_each_overlap(const AabbN<D>& box, std::uint32_t first, std::uint32_t last,
                        Report&& report) const;

  Options options_{};
  GridMapping<D> grid_{};
  CellN<D> padded_{1};              // cells per axis with the border: grid_.dims + 2
  std::uint32_t cells_ = 1;         // cells with the border: the product of padded_
  float chosen_cell_size_ = 0.0f;   // from the data at build; kept by update
  int count_ = 0;
  std::uint32_t small_ = 0;         // binned boxes: entries [0, small_) of the sorted arrays
  LargePageVector<std::uint32_t> keys_;    // per box: its cell's key, or the big bucket
  LargePageVector<std::uint32_t> starts_;  // per cell: first entry; starts_[c + 1] ends cell c
  // The entries sorted by key, count_ + kPad of them: binned boxes (ids ascending in a cell),
  // then the big boxes. Their boxes are in coords_, one array per coordinate: coordinate k of
  // the min corner of entry e is coords_[k * stride_ + e], of the max corner
  // coords_[(D + k) * stride_ + e].
  LineVector<Record> records_;
  std::size_t stride_ = 0;
  LargePageVector<float> coords_;
  // On grids sorted band by band: where each band's records are distributed, the next free
  // slot of each, and the boxes of each band (the big bucket last) in the last call, kept
  // while the grid is (update sizes the regions from them).
  std::vector<std::uint32_t> band_starts_;
  std::vector<std::uint32_t> band_next_;
  std::vector<std::uint32_t> band_counts_;
  // On grids sorted band by band: each box at the slot of its record while the records are
  // distributed by band, so that sort_band reads a band's boxes in one sequential sweep
  // (not from the span, where they are scattered among the other bands' boxes).
  LineVector<AabbN<D>> staged_;
  // Slots per line buffer of a distribution by band (see bin): records and boxes of kLineSlots
  // slots fill whole cache lines (8 lines of records and 16 or 24 of boxes: a buffer is written
  // out in one burst of consecutive lines). Measured per frame at 1e6 objects
  // (update_and_find_pairs, interleaved runs, medians): 8 slots (one line of records) 19.0 ->
  // 64 slots 17.7 ns per object in 2D, 27.8 -> 26.7 in 3D; 128 no better.
  static constexpr std::uint32_t kLineSlots = 64;
  // One band's next slots while the records are distributed, written out kLineSlots at a time.
  struct alignas(64) BandLine {
    Record records[kLineSlots];
    AabbN<D> boxes[kLineSlots];
  };
  LineVector<BandLine> band_lines_;
  // On grids sorted band by band, one band at a time: its records and boxes by cell.
  std::vector<AabbN<D>> band_boxes_;
  std::vector<Record> band_records_;
  std::vector<std::uint32_t> band_cells_;  // one band's cell starts
  Window window_;                      // build_and_find_pairs on grids sorted by band
  bool small_pairs_done_ = false;      // bin found the small-small pairs into its sink
  // and the big-small ones into big_found_ (see list_big_by_band):
  struct BigRange {
    CellN<D> lo, hi;  // the cells of the small boxes that may meet it
  };
  std::vector<BigRange> big_ranges_;             // per big box
  std::vector<std::uint32_t> big_band_starts_;   // per band: its first in big_band_list_
  std::vector<std::uint32_t> big_band_list_;     // indices into big_, by band, ascending
  struct BigFound {
    std::uint32_t big;  // index into big_
    int id;             // the small box's id
  };
  std::vector<BigFound> big_found_;
  std::vector<BigFound> big_found_sorted_;         // finish_pairs' counting sort of big_found_
  std::vector<std::uint32_t> big_found_starts_;    // and its per-big-box starts
  std::vector<Entry> big_;             // big boxes, ids ascending
  std::vector<Entry> big_by_x_;        // big boxes by min x, for their sweep
  float big_max_width_ = 0.0f;         // the widest big box along x: queries search big_by_x_
  std::vector<float> scratch_;
};

using LooseGrid = LooseGridN<2>;
using LooseGrid3 = LooseGridN<3>;

}  // namespace collide
