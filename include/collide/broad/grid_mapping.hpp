#pragma once
/// @file
/// World coordinates to uniform-grid cells, shared by every grid broad phase: which cells a box
/// covers, which single cell owns a pair (so each pair is reported once), and the walk of a ray
/// through the cells (3D-DDA, Amanatides & Woo, "A Fast Voxel Traversal Algorithm for Ray
/// Tracing", Eurographics 1987).
///
/// Cell convention: cell c along an axis covers [origin + c*size, origin + (c+1)*size). Both
/// corners of a box use floor (the lesson's question "shouldn't max use ceil?": no — a box whose
/// max lies exactly on a cell boundary touches the next cell's boxes there, so it must be listed
/// in that cell too). Because floor((x - origin) / size) never decreases as x grows, the cell of
/// max(a, b) is the max of the cells, and this is what makes the one-owner rule exact.

#include <collide/broad/broad_phase.hpp>

#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace collide {

/// Integer cell coordinates in D dimensions.
template <int D>
using CellN = glm::vec<D, int, glm::defaultp>;

/// Most cells along one axis of any grid: cell coordinates stay far from int overflow.
inline constexpr double kMaxGridCellsPerAxis = 1073741824.0;  // 2^30
/// Most cells in the whole grid: a linear cell index fits in 62 bits.
inline constexpr double kMaxGridCells = 4.6e18;  // just under 2^62

/// Largest coordinate magnitude a grid lays cells over: FLT_MAX / 2 (about 1.7e38), so that the
/// difference of two coordinates within it (an extent, p - origin) stays finite in float. Every
/// finite box is still accepted and answered exactly: the grids keep a box that reaches beyond
/// (a box spanning [-2e38, 2e38], a point at 3e38) out of their cells, in the list of boxes
/// tested against all ("oversized", "big" or "outliers").
inline constexpr float kGridCoordinateLimit = std::numeric_limits<float>::max() / 2.0f;
/// Largest cell side of any grid (2^126): its inverse, 2^-126, is still a normal float, and a
/// grid over the widest extent (2 * kGridCoordinateLimit) has at most 6 of these cells per axis.
inline constexpr float kMaxCellSize = 0x1p126f;

/// A uniform grid laid over the world bounds of a set of boxes (clamped to kGridCoordinateLimit).
template <int D>
struct GridMapping {
  /// The region the cells cover: the world bounds of the boxes the grid was built from,
  /// clamped to [-kGridCoordinateLimit, kGridCoordinateLimit] on every axis.
  AabbN<D> bounds{};
  VecN<D> origin{0.0f};         ///< corner of cell 0 (= bounds.min)
  float cell_size = 1.0f;       ///< side of a square/cubic cell, world units
  float inv_cell_size = 1.0f;   ///< 1 / cell_size
  CellN<D> dims{1};             ///< cells per axis; cells run from 0 to dims - 1
  /// The world bounds reached beyond kGridCoordinateLimit, so `bounds` is only part of them:
  /// boxes not inside `bounds` must be kept out of the cells (cell_of_inside is only for points
  /// inside `bounds`; cell_of clamps, but queries and ray walks stop at `bounds`).
  bool partial = false;

  /// The cell holding `p`, clamped to the grid (points outside map to the nearest border cell).
  [[nodiscard]] CellN<D> cell_of(const VecN<D>& p) const noexcept {
    CellN<D> c;
    for (int k = 0; k < D; ++k) {
      const float v = (p[k] - origin[k]) * inv_cell_size;
      // Clamped into [0, dims - 1] before the conversion, where truncation is the floor: the
      // cell of floor then clamp, for every input, without a floor (which SSE2, having no round
      // instruction, does in a dozen instructions: about 5% of a world step's, in grid queries).
      // max(0, v) is v > 0 ? v : 0, so NaN lands on 0 rather than in an undefined float-to-int
      // conversion; both clamps are one instruction each, no branch.
      const float clamped = std::min(std::max(0.0f, v), static_cast<float>(dims[k] - 1));
      c[k] = static_cast<int>(clamped);
    }
    return c;
  }

  /// cell_of for a point inside `bounds` (every corner of the boxes the grid was built from):
  /// the same float arithmetic, so the same cell, without the clamps. Inside the bounds
  /// (p - origin) * inv_cell_size is >= 0 and at most the top cell, so truncation is floor.
  [[nodiscard]] CellN<D> cell_of_inside(const VecN<D>& p) const noexcept {
    CellN<D> c;
    for (int k = 0; k < D; ++k) c[k] = static_cast<int>((p[k] - origin[k]) * inv_cell_size);
    return c;
  }

  /// The single cell that reports the pair (a, b) of overlapping boxes: the one holding the
  /// min corner of their intersection. Both boxes cover it, so each pair is found in exactly
  /// one cell without any set of already-reported pairs.
  [[nodiscard]] CellN<D> owner_cell(const AabbN<D>& a, const AabbN<D>& b) const noexcept {
    return cell_of(glm::max(a.min, b.min));
  }

  /// Number of cells the box covers (as a double: a huge box may cover more than 2^63).
  [[nodiscard]] double cell_count(const AabbN<D>& box) const noexcept {
    const CellN<D> lo = cell_of(box.min), hi = cell_of(box.max);
    double n = 1.0;
    for (int k = 0; k < D; ++k) n *= static_cast<double>(hi[k] - lo[k] + 1);
    return n;
  }

  /// Linear index of a cell, x fastest: below kMaxGridCells by construction.
  [[nodiscard]] std::uint64_t linear_index(const CellN<D>& c) const noexcept {
    std::uint64_t key = 0;
    for (int k = D - 1; k >= 0; --k) {
      key = key * static_cast<std::uint64_t>(dims[k]) + static_cast<std::uint64_t>(c[k]);
    }
    return key;
  }
};

/// Whether `c` lies in the cell range [lo, hi] on every axis.
template <int D>
[[nodiscard]] constexpr bool cell_in_range(const CellN<D>& c, const CellN<D>& lo,
                                           const CellN<D>& hi) noexcept {
  for (int k = 0; k < D; ++k) {
    if (c[k] < lo[k] || c[k] > hi[k]) return false;
  }
  return true;
}

/// Calls `visit(cell)` for every cell in [lo, hi], x fastest. `visit` returns false to stop;
/// returns false when stopped.
template <int D, class Visit>
bool for_each_cell(const CellN<D>& lo, const CellN<D>& hi, Visit&& visit) {
  CellN<D> c = lo;
  for (;;) {
    if (!visit(c)) return false;
    int k = 0;
    for (; k < D; ++k) {
      if (c[k] < hi[k]) {
        ++c[k];
        break;
      }
      c[k] = lo[k];
    }
    if (k == D) return true;
  }
}

/// Calls `visit(cell, first_axes)` for every cell in [lo, hi], x fastest, where bit k of
/// `first_axes` is set when cell[k] == lo[k]: whether the cell is the box's first along axis k.
template <int D, class Visit>
void for_each_cell_of_range(const CellN<D>& lo, const CellN<D>& hi, Visit&& visit) {
  if constexpr (D == 2) {
    for (int y = lo.y; y <= hi.y; ++y) {
      const std::uint32_t fy = y == lo.y ? 2u : 0u;
      for (int x = lo.x; x <= hi.x; ++x) visit(CellN<2>{x, y}, fy | (x == lo.x ? 1u : 0u));
    }
  } else {
    for (int z = lo.z; z <= hi.z; ++z) {
      const std::uint32_t fz = z == lo.z ? 4u : 0u;
      for (int y = lo.y; y <= hi.y; ++y) {
        const std::uint32_t fyz = fz | (y == lo.y ? 2u : 0u);
        for (int x = lo.x; x <= hi.x; ++x) visit(CellN<3>{x, y, z}, fyz | (x == lo.x ? 1u : 0u));
      }
    }
  }
}

/// `first_axes` with every axis set: the cell is the box's min-corner cell.
template <int D>
inline constexpr std::uint32_t kAllAxes = (1u << D) - 1u;

/// A box stored in a cell, grids keeping their boxes in cell order: a copy of the box (so the
/// pair loop reads one cell's boxes contiguously), its id, and on which axes this cell is the
/// box's first (bit k set when the cell's coordinate k is that of the box's min corner).
///
/// The owner rule in two ORs: two boxes covering cell c both have min-corner cells <= c, so
/// the cell of the min corner of their intersection, max(lo_a, lo_b), equals c on axis k exactly
/// when lo_a[k] == c[k] or lo_b[k] == c[k]. Hence c owns the pair exactly when
/// (a.first_axes | b.first_axes) == kAllAxes<D> (GridMapping::owner_cell, without arithmetic).
template <int D>
struct GridEntry {
  AabbN<D> box;
  int id;
  std::uint32_t first_axes;
};

/// Appends the pairs that one cell owns, given the cell's entries with ids ascending: every
/// overlapping pair (a.id, b.id) whose intersection has its min corner in this cell.
template <int D>
void append_cell_pairs(std::span<const GridEntry<D>> cell, PairList& pairs) {
  const std::size_t count = cell.size();
  for (std::size_t e = 0; e + 1 < count; ++e) {
    const GridEntry<D> a = cell[e];
    for (std::size_t f = e + 1; f < count; ++f) {
      const GridEntry<D>& b = cell[f];
      if ((a.first_axes | b.first_axes) == kAllAxes<D> && overlap(a.box, b.box)) {
        pairs.emplace_back(a.id, b.id);
      }
    }
  }
}

/// Bounds of all boxes; an empty span gives the zero box.
template <int D>
[[nodiscard]] AabbN<D> bounds_of(std::span<const AabbN<D>> boxes) noexcept {
  if (boxes.empty()) return {};
  AabbN<D> b = boxes[0];
  for (const AabbN<D>& box : boxes) b = merge(b, box);
  return b;
}

/// validate_boxes and bounds_of in one pass over the boxes: the bounds of valid boxes, or
/// InvalidInput naming the first bad box (as validate_boxes).
template <int D>
[[nodiscard]] AabbN<D> checked_bounds_of(std::span<const AabbN<D>> boxes);

/// The part of `bounds` (min <= max) a grid lays cells over: clamped to
/// [-kGridCoordinateLimit, kGridCoordinateLimit] on every axis (a world wholly beyond the limit
/// gets the point of the limit nearest to it). `partial` is set when anything was cut off.
template <int D>
[[nodiscard]] AabbN<D> grid_region(const AabbN<D>& bounds, bool& partial) noexcept {
  AabbN<D> region;
  partial = false;
  for (int k = 0; k < D; ++k) {
    // (written so that a NaN would land on the limit rather than pass through)
    const float lo = bounds.min[k] >= -kGridCoordinateLimit ? bounds.min[k] : -kGridCoordinateLimit;
    const float hi = bounds.max[k] <= kGridCoordinateLimit ? bounds.max[k] : kGridCoordinateLimit;
    partial = partial || lo != bounds.min[k] || hi != bounds.max[k];
    region.min[k] = std::min(lo, kGridCoordinateLimit);
    region.max[k] = std::max(hi, -kGridCoordinateLimit);
  }
  return region;
}

/// A grid over `bounds` (min <= max; infinite or beyond kGridCoordinateLimit is clamped to it,
/// setting `partial`) with cells of `cell_size` (kept in [FLT_MIN, kMaxCellSize]; NaN gives
/// kMaxCellSize), enlarged when needed so that no axis has more than kMaxGridCellsPerAxis cells
/// and the grid no more than kMaxGridCells: results stay exact, only the cells get coarser. This
/// is what lets positions 1e6 from the origin work. Every value it computes is finite, so the
/// doubling of the cell size ends (at kMaxCellSize at the latest, where every grid fits).
template <int D>
[[nodiscard]] GridMapping<D> make_grid_mapping(const AabbN<D>& bounds, float cell_size) noexcept {
  GridMapping<D> g;
  g.bounds = grid_region(bounds, g.partial);
  g.origin = g.bounds.min;
  const VecN<D> extent = g.bounds.max - g.bounds.min;  // at most FLT_MAX: finite
  double size = cell_size >= std::numeric_limits<float>::min()
                    ? std::min(cell_size, kMaxCellSize)
                    : (cell_size > 0.0f ? std::numeric_limits<float>::min() : kMaxCellSize);
  for (;;) {
    double total = 1.0;
    bool fits = true;
    for (int k = 0; k < D; ++k) {
      const double n = std::floor(static_cast<double>(extent[k]) / size) + 2.0;
      fits = fits && n <= kMaxGridCellsPerAxis;
      total *= n;
    }
    if (fits && total <= kMaxGridCells) break;
    size *= 2.0;
    if (size >= static_cast<double>(kMaxCellSize)) {
      size = kMaxCellSize;  // at most 6 cells per axis: fits
      break;
    }
  }
  g.cell_size = static_cast<float>(size);
  g.inv_cell_size = 1.0f / g.cell_size;
  for (int k = 0; k < D; ++k) {
    // The same float arithmetic as cell_of, so the max corner's cell is always inside the grid.
    const float top = std::floor((g.bounds.max[k] - g.origin[k]) * g.inv_cell_size);
    g.dims[k] = static_cast<int>(top) + 1;
  }
  return g;
}

/// Smallest cell size as a fraction of the largest coordinate magnitude of the world: a cell
/// must stay well above the float spacing of the coordinates it divides (2^-23 relative).
inline constexpr float kCellSizeResolution = 1e-5f;

/// Boxes whose sizes suggest_cell_size looks at, at most: all of them up to this count, else
/// this many spread evenly through the span (the median of a sample that size is within a few
/// percent of the true one, and the cell size is a heuristic: results stay exact).
inline constexpr int kCellSizeSamples = 4096;

/// A cell size for boxes of these sizes: twice the median of their largest sides (over at most
/// kCellSizeSamples of them), so a typical box covers 1 to 2 cells per axis. Points-only input
/// falls back to the spacing of n points spread over the bounds. Never below the float
/// resolution of the world bounds, never above kMaxCellSize. `scratch` is reused to avoid
/// allocation.
template <int D>
[[nodiscard]] float suggest_cell_size(std::span<const AabbN<D>> boxes, std::vector<float>& scratch);
/// suggest_cell_size when the bounds of the boxes are known already.
template <int D>
[[nodiscard]] float suggest_cell_size(std::span<const AabbN<D>> boxes, const AabbN<D>& bounds,
                                      std::vector<float>& scratch);
/// The largest side of each box, or of an even, deterministic stride of kCellSizeSamples boxes
/// when there are more, into `out` (cleared first): what cell sizes are chosen from.
template <int D>
void sample_largest_sides(std::span<const AabbN<D>> boxes, std::vector<float>& out);

/// Where a ray enters a grid's bounds: the fraction (negative when it misses them within the
/// walk's max fraction) and the cell there. walk_length finds it and walk_cells starts from it.
template <int D>
struct RayGridEntry {
  float fraction = -1.0f;
  CellN<D> cell{0};
};

/// Where `ray` (prepared for box tests as `slab`) enters the bounds of `g` within [0,
/// max_fraction] (RayGridEntry).
template <int D>
[[nodiscard]] RayGridEntry<D> ray_grid_entry(const GridMapping<D>& g, const RayN<D>& ray, const SlabRayN<D>& slab,
                                             float max_fraction) noexcept {
  RayGridEntry<D> entry;
  entry.fraction = slab.fraction(g.bounds, max_fraction);
  if (entry.fraction >= 0.0f) entry.cell = g.cell_of(ray.at(entry.fraction));
  return entry;
}

/// At most how many cells walk_cells visits for this ray within [0, max_fraction]: one plus the
/// cells stepped over on each axis between the cell where it enters the grid's bounds (`entry`,
/// from ray_grid_entry with the same max fraction) and the cell of its end (clamped to the
/// grid); 0 when it misses the bounds. A grid widened to 2^30 cells per axis (boxes 1e38 apart)
/// can make this a billion: the grids then test their boxes one by one instead of walking (as
/// their AABB queries do for a range wider than the occupied cells).
template <int D>
[[nodiscard]] double walk_length(const GridMapping<D>& g, const RayN<D>& ray, const RayGridEntry<D>& entry,
                                 float max_fraction) noexcept {
  if (entry.fraction < 0.0f) return 0.0;
  // The cell along each axis never goes back as the fraction grows (cell_of is monotone).
  const CellN<D> to = g.cell_of(ray.at(max_fraction));
  double steps = 1.0;
  for (int k = 0; k < D; ++k) steps += std::abs(static_cast<double>(to[k]) - static_cast<double>(entry.cell[k]));
  return steps;
}
/// walk_length for a ray not prepared as a SlabRayN.
template <int D>
[[nodiscard]] double walk_length(const GridMapping<D>& g, const RayN<D>& ray, float max_fraction) noexcept {
  return walk_length(g, ray, ray_grid_entry(g, ray, SlabRayN<D>(ray), max_fraction), max_fraction);
}

/// Walks the cells the ray crosses, in order along the ray, within [0, max_fraction], clipped to
/// the grid bounds: 3D-DDA (Amanatides & Woo 1987), the same code for 2D and 3D. `visit(cell,
/// max_fraction)` returns the new max_fraction (smaller clips the walk, 0 stops it). At a tie
/// (the ray through a cell corner) it steps one axis at a time, so no cell the ray touches is
/// skipped. `entry` is where the ray enters the grid's bounds (ray_grid_entry with the same max
/// fraction: a caller that asked walk_length first has it already).
template <int D, class Visit>
void walk_cells(const GridMapping<D>& g, const RayN<D>& ray, const RayGridEntry<D>& entry, float max_fraction,
                Visit&& visit) {
  if (entry.fraction < 0.0f) return;
  CellN<D> cell = entry.cell;
  CellN<D> step{0};
  double t_next[D];   // fraction at which the ray crosses the next boundary on each axis
  double t_delta[D];  // fraction to cross one whole cell on each axis
  for (int k = 0; k < D; ++k) {
    const double d = ray.translation[k];
    if (d == 0.0) {
      t_next[k] = std::numeric_limits<double>::infinity();
      t_delta[k] = 0.0;
      continue;
    }
    step[k] = d > 0.0 ? 1 : -1;
    const double boundary = static_cast<double>(g.origin[k]) +
                            static_cast<double>(cell[k] + (d > 0.0 ? 1 : 0)) * g.cell_size;
    t_next[k] = (boundary - static_cast<double>(ray.origin[k])) / d;
    t_delta[k] = static_cast<double>(g.cell_size) / std::abs(d);
  }
  float limit = max_fraction;
  for (;;) {
    const float r = visit(cell, limit);
    if (r < limit) limit = r;
    if (limit <= 0.0f) return;
    // The next boundary crossed; at a tie (a cell corner) an axis stepping up goes first:
    // the corner point itself belongs to the cell above on those axes (floor), so that cell
    // must be visited before the axes stepping down move on.
    int axis = 0;
    for (int k = 1; k < D; ++k) {
      if (t_next[k] < t_next[axis] || (t_next[k] == t_next[axis] && step[axis] < step[k])) {
        axis = k;
      }
    }
    if (t_next[axis] > static_cast<double>(limit)) return;
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= g.dims[axis]) return;
    t_next[axis] += t_delta[axis];
  }
}
/// walk_cells for a ray prepared for box tests as `slab` (SlabRayN).
template <int D, class Visit>
void walk_cells(const GridMapping<D>& g, const RayN<D>& ray, const SlabRayN<D>& slab, float max_fraction,
                Visit&& visit) {
  walk_cells(g, ray, ray_grid_entry(g, ray, slab, max_fraction), max_fraction, std::forward<Visit>(visit));
}
/// walk_cells for a ray not prepared as a SlabRayN.
template <int D, class Visit>
void walk_cells(const GridMapping<D>& g, const RayN<D>& ray, float max_fraction, Visit&& visit) {
  walk_cells(g, ray, SlabRayN<D>(ray), max_fraction, std::forward<Visit>(visit));
}

}  // namespace collide
