#include <collide/broad/hierarchical_grid.hpp>

#include "oversized_boxes.hpp"

#include <collide/core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace collide {

namespace {

/// Levels below and above the base: cells from base / 4^8 to base * 4^24.
constexpr int kFinestLevel = -8;
constexpr int kCoarsestLevel = 24;

/// A level holding fewer boxes than 1 / kMinorityRatio of the next occupied coarser level's
/// joins that level (its boxes fit its cells too). Its own fine cells would be nearly empty: a
/// ray's walk through them visits kLevelRatio times the cells of the coarser walk for few
/// boxes (a world's temporal broad phase at 1e4 bodies: 29 cells a ray at the fine level for
/// 0.08 occupied, against 5.4 at the level holding 95% of the boxes), while its boxes' pairs
/// cost about what they did: a fine box looked up the coarser cells anyway.
constexpr std::size_t kMinorityRatio = 8;
/// level_of_ for a box in no level (a big one).
constexpr std::int8_t kNoLevel = -128;

/// The first level whose cells are at least `largest_side` wide.
int level_for(float largest_side, float base) noexcept {
  int level = 0;
  float cell = base;
  if (largest_side > cell) {
    while (largest_side > cell && level < kCoarsestLevel) {
      cell *= HierarchicalGridN<2>::kLevelRatio;
      ++level;
    }
  } else {
    while (level > kFinestLevel && largest_side <= cell / HierarchicalGridN<2>::kLevelRatio) {
      cell /= HierarchicalGridN<2>::kLevelRatio;
      --level;
    }
  }
  return level;
}

}  // namespace

template <int D>
HierarchicalGridN<D>::HierarchicalGridN(Options options) : options_(options) {
  if (!std::isfinite(options.base_cell_size) || options.base_cell_size < 0.0f) {
    throw InvalidInput("HierarchicalGrid options base_cell_size: negative or not finite");
  }
}

template <int D>
void HierarchicalGridN<D>::build(std::span<const AabbN<D>> boxes) {
  const AabbN<D> world = checked_bounds_of(boxes);
  base_ = options_.base_cell_size > 0.0f ? options_.base_cell_size
                                         : suggest_cell_size(boxes, world, scratch_);
  rebuild(boxes, world);
}

template <int D>
void HierarchicalGridN<D>::update(std::span<const AabbN<D>> boxes) {
  if (base_ == 0.0f) {
    build(boxes);
    return;
  }
  rebuild(boxes, checked_bounds_of(boxes));
}

template <int D>
void HierarchicalGridN<D>::rebuild(std::span<const AabbN<D>> boxes, const AabbN<D>& world) {
  boxes_.assign(boxes.begin(), boxes.end());
  const float base = base_;
  for (Level& level : levels_) level.ids.clear();
  big_.clear();
  is_big_.assign(boxes.size(), 0);
  // Boxes larger than the cells of the coarsest level (or wider than float: an infinite side),
  // and boxes reaching beyond kGridCoordinateLimit, where no level lays cells, are tested
  // against all instead: in the coarsest level such a box could cover 2^60 cells.
  bool partial = false;
  const AabbN<D> region = grid_region(world, partial);
  const double coarsest = static_cast<double>(base) * std::pow(static_cast<double>(kLevelRatio), kCoarsestLevel);
  // The finest level whose cells stay above the float resolution of the world's coordinates
  // (kCellSizeResolution, as suggest_cell_size keeps the base): cells of a few float spacings
  // put a ray's walk (double arithmetic) and the boxes' cells (float) a cell apart.
  float magnitude = 0.0f;
  for (int k = 0; k < D; ++k) magnitude = std::max({magnitude, std::abs(region.min[k]), std::abs(region.max[k])});
  const double resolution = static_cast<double>(kCellSizeResolution) * magnitude;
  int finest = kFinestLevel;
  while (finest < 0 && static_cast<double>(base) * std::pow(static_cast<double>(kLevelRatio), finest) < resolution) ++finest;
  // (no box can be big when the world fits in the region and in one coarsest cell: the test
  // is skipped, as it is for every ordinary world)
  double world_side = 0.0;
  for (int k = 0; k < D; ++k) world_side = std::max(world_side, static_cast<double>(world.max[k]) - world.min[k]);
  const bool may_be_big = partial || world_side > coarsest;
  // Each box's level in two passes: count the boxes of each level (levels finer than `finest`
  // raised to it; big boxes in none), choose where minority levels go (kMinorityRatio), then
  // place the ids in ascending order.
  const auto slot = [](int exponent) { return static_cast<std::size_t>(exponent - kFinestLevel); };
  const int n = size();
  level_of_.resize(boxes.size());
  std::array<int, kCoarsestLevel - kFinestLevel + 1> count{};
  for (int i = 0; i < n; ++i) {
    const VecN<D> s = boxes[i].size();
    float largest = s[0];
    for (int k = 1; k < D; ++k) largest = std::max(largest, s[k]);
    if (may_be_big && (static_cast<double>(largest) > coarsest || (partial && !contains(region, boxes[i])))) {
      big_.push_back(i);
      is_big_[static_cast<std::size_t>(i)] = 1;
      level_of_[static_cast<std::size_t>(i)] = kNoLevel;
      continue;
    }
    const int exponent = std::max(level_for(largest, base), finest);
    level_of_[static_cast<std::size_t>(i)] = static_cast<std::int8_t>(exponent);
    ++count[slot(exponent)];
  }
  std::array<std::int8_t, kCoarsestLevel - kFinestLevel + 1> into{};  // the level each joins
  for (int e = kFinestLevel; e <= kCoarsestLevel; ++e) into[slot(e)] = static_cast<std::int8_t>(e);
  for (int e = kFinestLevel; e <= kCoarsestLevel; ++e) {
    const int fine = count[slot(e)];
    if (fine == 0) continue;
    int c = e + 1;
    while (c <= kCoarsestLevel && count[slot(c)] == 0) ++c;
    if (c > kCoarsestLevel) break;
    if (static_cast<std::size_t>(fine) * kMinorityRatio >= static_cast<std::size_t>(count[slot(c)])) continue;
    count[slot(c)] += fine;  // (and it may then join the next in turn)
    into[slot(e)] = static_cast<std::int8_t>(c);
  }
  // A level that joined one which joined another goes to the last: resolved coarse to fine,
  // each pointing at a coarser level already resolved.
  for (int e = kCoarsestLevel; e >= kFinestLevel; --e) into[slot(e)] = into[slot(into[slot(e)])];
  Level* last = nullptr;  // the level of the previous box: runs of one level skip the search
  for (int i = 0; i < n; ++i) {
    const int from = level_of_[static_cast<std::size_t>(i)];
    if (from == kNoLevel) continue;
    const int exponent = into[slot(from)];
    if (last == nullptr || last->exponent != exponent) {
      auto it = std::lower_bound(levels_.begin(), levels_.end(), exponent,
                                 [](const Level& l, int e) { return l.exponent < e; });
      if (it == levels_.end() || it->exponent != exponent) {
        it = levels_.insert(it, Level{});
        it->exponent = exponent;
      }
      last = &*it;
    }
    last->ids.push_back(i);
  }
  for (Level& level : levels_) {
    const float cell = base * std::pow(kLevelRatio, static_cast<float>(level.exponent));
    level.grid.build_subset(boxes_, level.ids, make_grid_mapping(world, cell));
  }
}

namespace {

/// Occupied cells, and boxes, per piece of find_pairs' work: at most a few hundred
/// microseconds ...
constexpr int kCellsPerPiece = 4096;
constexpr int kBoxesPerPiece = 2048;
/// ... and at least a few microseconds (a task's cost on the workers).
constexpr int kMinCellsPerPiece = 128;
constexpr int kMinBoxesPerPiece = 64;
/// Pieces per worker wanted (more than one: pieces differ in cost, and a worker that finishes
/// early takes another).
constexpr int kPiecesPerWorker = 4;

}  // namespace

template <int D>
bool HierarchicalGridN<D>::coarse_looks_up_fine(int fine, int coarse) const noexcept {
  // A fine box covers at most 2 cells per axis of a coarser level; a coarse box, up to
  // kLevelRatio^steps + 1 per axis of the finer one (its side is at most its own cell's).
  // Cells visited either way, in double (no overflow for distant levels).
  const Level& f = levels_[static_cast<std::size_t>(fine)];
  const Level& c = levels_[static_cast<std::size_t>(coarse)];
  const double per_axis = std::pow(static_cast<double>(kLevelRatio), c.exponent - f.exponent) + 1.0;
  const auto fine_boxes = static_cast<double>(f.ids.size());
  const auto coarse_boxes = static_cast<double>(c.ids.size());
  return coarse_boxes * std::pow(per_axis, D) < fine_boxes * static_cast<double>(1 << D);
}

template <int D>
template <class Visit>
void HierarchicalGridN<D>::for_each_piece(int cells_per_piece, int boxes_per_piece, Visit&& visit) const {
  const auto level_total = static_cast<int>(levels_.size());
  for (int l = 0; l < level_total; ++l) {
    if (levels_[static_cast<std::size_t>(l)].ids.empty()) continue;
    const int cells = levels_[static_cast<std::size_t>(l)].grid.cell_count();
    for (int c = 0; c < cells; c += cells_per_piece) {
      visit(Piece{l, -1, c, std::min(cells, c + cells_per_piece), false});
    }
    for (int m = l + 1; m < level_total; ++m) {
      if (levels_[static_cast<std::size_t>(m)].ids.empty()) continue;
      // The boxes of whichever level visits fewer cells look up the other's.
      const bool from_coarse = coarse_looks_up_fine(l, m);
      const auto boxes = static_cast<int>(levels_[static_cast<std::size_t>(from_coarse ? m : l)].ids.size());
      for (int b = 0; b < boxes; b += boxes_per_piece) {
        visit(Piece{l, m, b, std::min(boxes, b + boxes_per_piece), from_coarse});
      }
    }
  }
}

template <int D>
void HierarchicalGridN<D>::piece_pairs(const Piece& piece, PairList& pairs) const {
  const Level& level = levels_[static_cast<std::size_t>(piece.level)];
  if (piece.coarse < 0) {
    level.grid.append_cell_range_pairs(pairs, piece.begin, piece.end);
    return;
  }
  // Each box of one level against the other: that level's grid query (each overlapping box
  // once, in cell order; a level holds no oversized boxes, its grid is built from a subset).
  const Level& coarse = levels_[static_cast<std::size_t>(piece.coarse)];
  const Level& from = piece.from_coarse ? coarse : level;
  const SortedGridN<D>& into = piece.from_coarse ? level.grid : coarse.grid;
  for (int i = piece.begin; i < piece.end; ++i) {
    const int a = from.ids[static_cast<std::size_t>(i)];
    into.query(boxes_[a], [&](int b) {
      pairs.emplace_back(std::min(a, b), std::max(a, b));
      return true;
    });
  }
}

template <int D>
void HierarchicalGridN<D>::find_pairs(PairList& pairs) const {
  pairs.clear();
  for_each_piece(kCellsPerPiece, kBoxesPerPiece, [&](const Piece& piece) { piece_pairs(piece, pairs); });
  detail::oversized_pairs<D>(big_, is_big_, boxes_, pairs);
}

template <int D>
void HierarchicalGridN<D>::find_pairs(PairList& pairs, TaskScheduler* scheduler) {
  if (scheduler == nullptr || scheduler->worker_count() < 2) {
    find_pairs(pairs);
    return;
  }
  // Piece sizes for kPiecesPerWorker pieces a worker over the largest level's cells and boxes.
  int most_cells = 0, most_boxes = 0;
  for (const Level& level : levels_) {
    most_cells = std::max(most_cells, level.grid.cell_count());
    most_boxes = std::max(most_boxes, static_cast<int>(level.ids.size()));
  }
  const int wanted = kPiecesPerWorker * scheduler->worker_count();
  const int cells_per_piece = std::clamp(most_cells / wanted, kMinCellsPerPiece, kCellsPerPiece);
  const int boxes_per_piece = std::clamp(most_boxes / wanted, kMinBoxesPerPiece, kBoxesPerPiece);
  pieces_.clear();
  for_each_piece(cells_per_piece, boxes_per_piece, [&](const Piece& piece) { pieces_.push_back(piece); });
  if (piece_pairs_.size() < pieces_.size()) piece_pairs_.resize(pieces_.size());
  parallel_for(scheduler, static_cast<int>(pieces_.size()), 1, [&](int begin, int end, int) {
    for (int p = begin; p < end; ++p) {
      PairList& out = piece_pairs_[static_cast<std::size_t>(p)];
      out.clear();
      piece_pairs(pieces_[static_cast<std::size_t>(p)], out);
    }
  });
  pairs.clear();
  for (std::size_t p = 0; p < pieces_.size(); ++p) {
    pairs.insert(pairs.end(), piece_pairs_[p].begin(), piece_pairs_[p].end());
  }
  detail::oversized_pairs<D>(big_, is_big_, boxes_, pairs);
}

template <int D>
void HierarchicalGridN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  if (!detail::oversized_query<D>(big_, boxes_, box, callback)) return;
  bool go_on = true;
  for (const Level& level : levels_) {
    if (!go_on) return;
    level.grid.query(box, [&](int id) { return go_on = callback(id); });
  }
}

template <int D>
void HierarchicalGridN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  for (const int b : big_) {
    if (contains(boxes_[static_cast<std::size_t>(b)], point) && !callback(b)) return;
  }
  bool go_on = true;
  for (const Level& level : levels_) {
    if (!go_on) return;
    level.grid.query_point(point, [&](int id) { return go_on = callback(id); });
  }
}

template <int D>
void HierarchicalGridN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  ray_cast(ray, SlabRayN<D>(ray), callback);
}

template <int D>
void HierarchicalGridN<D>::ray_cast(const RayN<D>& ray, const SlabRayN<D>& slab, RayCallback callback) const {
  float limit = detail::oversized_ray_cast<D>(big_, boxes_, slab, 1.0f, callback);
  for (const Level& level : levels_) {
    if (limit <= 0.0f) return;
    // A level's walk starts at the clip of earlier levels: the boxes it gives met the ray
    // within it (each grid entry holds its box), and returning `limit` clips the walk.
    level.grid.ray_cast(ray, slab, [&](int id, float) {
      const float r = callback(id, limit);
      if (r < limit) limit = r;
      return limit;
    }, limit);
  }
}

template <int D>
int HierarchicalGridN<D>::level_count() const noexcept {
  return static_cast<int>(std::count_if(levels_.begin(), levels_.end(),
                                        [](const Level& l) { return !l.ids.empty(); }));
}

template <int D>
std::size_t HierarchicalGridN<D>::memory_bytes() const noexcept {
  std::size_t bytes = boxes_.capacity() * sizeof(AabbN<D>) + scratch_.capacity() * sizeof(float) +
                      levels_.capacity() * sizeof(Level) + big_.capacity() * sizeof(int) +
                      is_big_.capacity() + level_of_.capacity();
  for (const Level& level : levels_) {
    bytes += level.ids.capacity() * sizeof(int) + level.grid.memory_bytes();
  }
  return bytes;
}

template class HierarchicalGridN<2>;
template class HierarchicalGridN<3>;
static_assert(BroadPhase<HierarchicalGridN<2>, 2> && BroadPhase<HierarchicalGridN<3>, 3>);

}  // namespace collide
