#pragma once
/// @file
/// A hierarchical grid: levels of cells whose size grows by 4 from one level to the next, so
/// that 0.1-unit and 100-unit objects mix. Each box lives in one level only, the first whose
/// cells are at least as large as the box, so it covers at most 2 cells per axis; small boxes
/// do not share cells with (and get tested against everything in) the cells of big ones, and a
/// big box does not fill thousands of small cells. (Ericson, Real-Time Collision Detection,
/// 7.2.2; Mirtich, "Efficient Algorithms for Two-Phase Collision Detection", 1997.) A level
/// that would hold under an eighth of the boxes of the next occupied coarser level joins that
/// level instead: a ray would walk its fine cells, nearly all empty, for few boxes, while its
/// boxes' pairs cost about as much in the coarser cells (they looked those up anyway).
///
/// Each level is a SortedGrid over its boxes. Pairs inside a level come from that level's
/// cells; a box meets the boxes of every coarser level by looking up the at most 2^D cells it
/// covers there, and the pair is reported only from the cell (of the coarser level) holding the
/// min corner of the intersection, so each pair comes out once. Where a coarser level holds far
/// fewer boxes (a few large ones over thousands of small), its boxes look up the finer level's
/// cells instead: fewer cells visited in all (kLevelRatio^D fine cells a step, against 2^D
/// coarse cells for each fine box).
///
/// A box larger than the cells of the coarsest level (base * 4^24), or reaching beyond
/// kGridCoordinateLimit (about 1.7e38) where no level lays cells, is in no level: it is tested
/// against every box (as SortedGrid's oversized boxes), so any finite box is answered exactly.
///
/// Memory per object: about that of a SortedGrid entry (2^D cells at most, usually 1 to 2 per
/// axis), plus an int for its level and a byte.

#include <collide/broad/broad_phase.hpp>
#include <collide/broad/grid_mapping.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/core/task_scheduler.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace collide {

/// Multi-level uniform grid over boxes in D dimensions.
template <int D>
class HierarchicalGridN {
 public:
  /// What the constructor takes; it rejects bad values, naming the field.
  struct Options {
    /// Cell size of level 0 in world units; 0 (the default) chooses twice the median box size.
    /// Levels above are 4, 16, 64... times larger, levels below 4, 16... times smaller.
    float base_cell_size = 0.0f;
  };

  /// Cell size ratio between consecutive levels.
  static constexpr float kLevelRatio = 4.0f;

  HierarchicalGridN() = default;
  /// Throws InvalidInput for a negative or non-finite base cell size.
  explicit HierarchicalGridN(Options options);

  /// Rebuilds all levels. Throws InvalidInput for a non-finite box or min > max.
  void build(std::span<const AabbN<D>> boxes);
  /// Rebuilds from the moved boxes, keeping the base cell size chosen at build.
  void update(std::span<const AabbN<D>> boxes);

  /// Every overlapping pair once, i < j. Order: level by level (fine to coarse), in each level
  /// its own pairs then its boxes against each coarser level (or that level's boxes against
  /// it, where they visit fewer cells); the boxes in no level last.
  void find_pairs(PairList& pairs) const;
  /// find_pairs with its work cut into pieces (a level's cells, a level's boxes against a
  /// coarser level, in ranges: a few per worker, at most a few hundred microseconds each) that
  /// run on the scheduler's workers, each into its own list, the lists then joined in order:
  /// the same pairs in the same order for any schedule and worker count (null or one worker:
  /// find_pairs). Not to be called concurrently on one grid (the lists are members).
  void find_pairs(PairList& pairs, TaskScheduler* scheduler);
  /// Each id whose box overlaps `box` (touching counts), once.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Each id whose box contains `point` (boundary included), once.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Each level in turn, fine to coarse (not sorted by distance along the ray), each walked
  /// only up to the clip the hits so far left.
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;
  /// ray_cast with `slab`, the same ray prepared for box tests (SlabRayN(ray)) by a caller that
  /// tests boxes of its own with it: one preparation serves every level.
  void ray_cast(const RayN<D>& ray, const SlabRayN<D>& slab, RayCallback callback) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return static_cast<int>(boxes_.size()); }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;
  /// Levels holding at least one box in the last build.
  [[nodiscard]] int level_count() const noexcept;

 private:
  struct Level {
    int exponent = 0;        // cell size = base * kLevelRatio^exponent
    std::vector<int> ids;    // boxes in this level, ascending
    SortedGridN<D> grid;
  };

  void rebuild(std::span<const AabbN<D>> boxes, const AabbN<D>& world);

  /// A piece of find_pairs' work: level `level`'s own pairs in its occupied cells
  /// [begin, end) (coarse < 0), or its boxes ids[begin, end) against level `coarse`, or (when
  /// `from_coarse`) level `coarse`'s boxes ids[begin, end) against level `level`.
  struct Piece {
    int level;
    int coarse;
    int begin;
    int end;
    bool from_coarse = false;
  };
  /// True when level `coarse`'s boxes should look up level `fine`'s cells, rather than the
  /// other way round: fewer cells visited (the box counts and the levels' ratio decide).
  [[nodiscard]] bool coarse_looks_up_fine(int fine, int coarse) const noexcept;
  /// Calls visit(piece) for find_pairs' pieces in its order, cells and boxes cut in ranges of
  /// at most `cells_per_piece` and `boxes_per_piece` (any sizes give the same pairs in the same
  /// order once the pieces' lists are joined).
  template <class Visit>
  void for_each_piece(int cells_per_piece, int boxes_per_piece, Visit&& visit) const;
  /// Appends the pairs of one piece.
  void piece_pairs(const Piece& piece, PairList& pairs) const;

  Options options_{};
  float base_ = 0.0f;          // level 0 cell size chosen at build
  std::vector<AabbN<D>> boxes_;
  std::vector<Level> levels_;  // sorted by exponent; empty ones kept for reuse
  // Boxes in no level (larger than the coarsest cells, or reaching beyond kGridCoordinateLimit),
  // ascending, tested against every box; and a flag per box.
  std::vector<int> big_;
  std::vector<std::uint8_t> is_big_;
  std::vector<std::int8_t> level_of_;  // each box's level exponent while rebuilding (scratch)
  std::vector<float> scratch_;
  std::vector<Piece> pieces_;           // find_pairs with a scheduler: its pieces...
  std::vector<PairList> piece_pairs_;   // ... and the pairs of each
};

using HierarchicalGrid = HierarchicalGridN<2>;
using HierarchicalGrid3 = HierarchicalGridN<3>;

}  // namespace collide
