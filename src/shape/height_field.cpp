#include <collide/shape/height_field.hpp>

#include "watertight_ray.hpp"

#include <collide/core/config.hpp>
#include <collide/core/error.hpp>
#include <collide/shape/triangle_bvh.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace collide {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

/// A block's height range is widened by this fraction of the magnitudes involved (the range's
/// and the ray's) before a ray is said to pass above or below it: the ray's height at the block's
/// entry and exit is rounded, and a skipped block must really be missed.
constexpr float kHeightRangeSlack = 0x1p-20f;

/// A box query takes the cells within this fraction of a cell (relative to the cell coordinate,
/// plus as much absolute) beyond the ones its corners fall in: above the rounding of a division
/// and of a grid coordinate's product (a few 2^-24), far below a cell.
constexpr float kCellRangeSlack = 0x1p-20f;

/// The two triangles of cell (i, j), corners relative to the origin (grid space), as
/// HeightField::grid_corners orders them: even (p00, p01, p11), odd (p00, p11, p10). Four
/// sample reads for both, where grid_corners per triangle takes three each and a division.
COLLIDE_ALWAYS_INLINE std::array<std::array<Vec3, 3>, 2> cell_triangles(const HeightField& f, int i, int j) noexcept {
  const Vec3 p00 = f.grid_point(i, j), p11 = f.grid_point(i + 1, j + 1);
  return {{{p00, f.grid_point(i, j + 1), p11}, {p00, p11, f.grid_point(i + 1, j)}}};
}

/// Walks the cells of a grid (cells of `size`, corner 0 at the origin of grid space, cell indices
/// limited to [lo, hi] per axis) that the 2D path o + t d passes over, from t = t_in on, in
/// order: Amanatides & Woo 1987 (the next cell is across whichever boundary, x or z, the path
/// meets first; on a tie, across both, visiting the cell beside the corner too). Each boundary's
/// fraction is computed from the cell index, not accumulated, so rounding does not drift over
/// long walks. On an axis the path does not move along, the caller gives the cells it covers
/// (`still`: two when it runs exactly on a grid line, which both cells' triangles touch), and
/// every one of them is visited at each step. Calls visit(i, j), which returns false to stop;
/// the walk also ends when a cell's exit lies beyond `limit` (read after each step, so the
/// visitor may lower it) or the path leaves the index range.
template <class Visit>
void walk_grid(Vec2 o, Vec2 d, Vec2 size, glm::ivec2 lo, glm::ivec2 hi, const std::array<glm::ivec2, 2>& still, float t_in,
               const float& limit, Visit&& visit) {
  const Vec2 p = o + t_in * d;
  glm::ivec2 cell, step, extra(0);
  for (int a = 0; a < 2; ++a) {
    step[a] = d[a] > 0.0f ? 1 : d[a] < 0.0f ? -1 : 0;
    if (step[a] == 0) {
      cell[a] = std::max(still[a].x, lo[a]);
      extra[a] = std::min(still[a].y, hi[a]) - cell[a];
      if (extra[a] < 0) return;
      continue;
    }
    const float at = std::floor(p[a] / size[a]);
    // (p is within the field's box, up to rounding: the index is small; clamped into range)
    cell[a] = at < static_cast<float>(lo[a]) ? lo[a] : at > static_cast<float>(hi[a]) ? hi[a] : static_cast<int>(at);
  }
  auto visit_here = [&](glm::ivec2 c) {
    for (int i = c.x; i <= c.x + extra.x; ++i) {
      for (int j = c.y; j <= c.y + extra.y; ++j) {
        if (!visit(i, j)) return false;
      }
    }
    return true;
  };
  for (;;) {
    std::array<float, 2> exit{kInfinity, kInfinity};
    for (int a = 0; a < 2; ++a) {
      if (step[a] != 0) exit[a] = (static_cast<float>(cell[a] + (step[a] > 0 ? 1 : 0)) * size[a] - o[a]) / d[a];
    }
    if (!visit_here(cell)) return;
    const float t_out = std::min(exit[0], exit[1]);
    if (!(t_out <= limit)) return;
    if (exit[0] == exit[1]) {  // through a corner: the cell beside it along z, then on diagonally
      const glm::ivec2 side(cell.x, cell.y + step.y);
      if (side.y >= lo.y && side.y <= hi.y && !visit_here(side)) return;
      cell += step;
    } else {
      const int a = exit[0] < exit[1] ? 0 : 1;
      cell[a] += step[a];
    }
    if (cell.x < lo.x || cell.x > hi.x || cell.y < lo.y || cell.y > hi.y) return;
  }
}

/// On an axis the ray does not move along (translation 0 there), the cells (first, last) its
/// coordinate `v` (grid space) lies in: two when it is exactly on the line between them, as the
/// corners are computed (index * spacing).
glm::ivec2 still_cells(float v, float spacing, int cells) {
  const float at = std::floor(v / spacing);
  int k = at < 0.0f ? 0 : at > static_cast<float>(cells - 1) ? cells - 1 : static_cast<int>(at);
  glm::ivec2 range(k, k);
  // The line below or above cell k, if v is exactly on it (rounding of v / spacing aside).
  for (int line = k; line <= k + 1; ++line) {
    if (v == static_cast<float>(line) * spacing) range = glm::ivec2(std::max(line - 1, 0), std::min(line, cells - 1));
  }
  return range;
}

/// The ray cast behind both HeightField::ray_cast overloads. `on_hit(triangle, fraction, max)`
/// handles one crossing and returns the new max (<= 0 stops).
template <class OnHit>
void cast(const HeightField& f, const Ray3& local_ray, float max_fraction, OnHit&& on_hit) {
  // Grid space: relative to the origin.
  const Ray3 ray{local_ray.origin - f.origin, local_ray.translation};
  const detail::WatertightRay watertight(ray);
  if (!watertight.valid || !(max_fraction > 0.0f)) return;
  // The height range of the non-hole cells: the ray must pass through it.
  float lo_y = kInfinity, hi_y = -kInfinity;
  for (const auto& r : f.block_range) lo_y = std::min(lo_y, r[0]), hi_y = std::max(hi_y, r[1]);
  if (!(lo_y <= hi_y)) return;  // every cell a hole
  // Clip to the field's box (slab method; an axis the ray does not move along needs the origin
  // within that slab).
  const Vec3 box_min(0.0f, lo_y, 0.0f);
  const Vec3 box_max(static_cast<float>(f.cells_x()) * f.spacing.x, hi_y, static_cast<float>(f.cells_z()) * f.spacing.y);
  float t0 = 0.0f, t1 = max_fraction;
  for (int a = 0; a < 3; ++a) {
    const float o = ray.origin[a], d = ray.translation[a];
    if (d == 0.0f) {
      if (!(o >= box_min[a] && o <= box_max[a])) return;
      continue;
    }
    float near = (box_min[a] - o) / d, far = (box_max[a] - o) / d;
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
  }
  t1 *= kBvhSlabSlack;  // rounding must not cut off a hit on the box's boundary
  t0 /= kBvhSlabSlack;
  if (!(t0 <= t1)) return;

  const Vec2 o2(ray.origin.x, ray.origin.z), d2(ray.translation.x, ray.translation.z);
  const int b = kHeightFieldBlockCells;
  const Vec2 block_size = static_cast<float>(b) * f.spacing;
  // Axes the ray does not move along: the cells (and blocks) it stays over.
  std::array<glm::ivec2, 2> still_cell{glm::ivec2(0), glm::ivec2(0)}, still_block{glm::ivec2(0), glm::ivec2(0)};
  for (int a = 0; a < 2; ++a) {
    if (d2[a] != 0.0f) continue;
    still_cell[a] = still_cells(o2[a], f.spacing[a], a == 0 ? f.cells_x() : f.cells_z());
    still_block[a] = still_cell[a] / b;
  }
  float max_t = max_fraction;
  float limit = std::min(t1, max_t * kBvhSlabSlack);
  bool stopped = false;
  walk_grid(o2, d2, block_size, {0, 0}, {f.blocks_x - 1, f.blocks_z - 1}, still_block, t0, limit, [&](int bx, int bz) {
    const std::array<float, 2> range = f.block_range[static_cast<std::size_t>(bz) * f.blocks_x + bx];
    if (!(range[0] <= range[1])) return true;  // every cell a hole
    // The ray's heights over the block: over the part of the ray whose xz path is in the block's
    // rectangle (slabs in x and z, widened for rounding), within [t0, limit].
    float t_in = t0, t_out = limit;
    const Vec2 block_lo = Vec2(static_cast<float>(bx), static_cast<float>(bz)) * block_size;
    for (int a = 0; a < 2; ++a) {
      if (d2[a] == 0.0f) continue;
      float near = (block_lo[a] - o2[a]) / d2[a], far = (block_lo[a] + block_size[a] - o2[a]) / d2[a];
      if (near > far) std::swap(near, far);
      t_in = std::max(t_in, near / kBvhSlabSlack);
      t_out = std::min(t_out, far * kBvhSlabSlack);
    }
    const float ya = ray.origin.y + t_in * ray.translation.y;
    const float yb = ray.origin.y + t_out * ray.translation.y;
    const float pad = kHeightRangeSlack * (std::abs(range[0]) + std::abs(range[1]) + std::abs(ray.origin.y) +
                                           std::abs(ray.translation.y));
    if (!(std::max(ya, yb) >= range[0] - pad && std::min(ya, yb) <= range[1] + pad)) return true;  // above or below
    const glm::ivec2 lo(bx * b, bz * b);
    const glm::ivec2 hi(std::min(lo.x + b, f.cells_x()) - 1, std::min(lo.y + b, f.cells_z()) - 1);
    walk_grid(o2, d2, f.spacing, lo, hi, still_cell, std::max(t_in, t0), limit, [&](int i, int j) {
      const std::uint32_t c = static_cast<std::uint32_t>(j) * static_cast<std::uint32_t>(f.cells_x()) + static_cast<std::uint32_t>(i);
      if (f.is_hole(c)) return true;
      const std::array<std::array<Vec3, 3>, 2> corners = cell_triangles(f, i, j);
      for (std::uint32_t t = 2 * c; t < 2 * c + 2; ++t) {
        const std::array<Vec3, 3>& p = corners[t - 2 * c];
        const float hit = watertight.fraction(p[0], p[1], p[2], max_t);
        if (hit < 0.0f) continue;
        max_t = on_hit(t, hit, max_t);
        if (!(max_t > 0.0f)) {
          stopped = true;
          return false;
        }
      }
      limit = std::min(t1, max_t * kBvhSlabSlack);
      return true;
    });
    return !stopped;
  });
}

}  // namespace

std::array<Vec3, 3> HeightField::grid_corners(std::uint32_t t) const noexcept {
  const std::uint32_t c = t / 2;
  const int i = static_cast<int>(c % static_cast<std::uint32_t>(cells_x()));
  const int j = static_cast<int>(c / static_cast<std::uint32_t>(cells_x()));
  return cell_triangles(*this, i, j)[t % 2];
}

std::uint32_t HeightField::corner_sample(std::uint32_t t, int k) const noexcept {
  const std::uint32_t c = t / 2;
  const auto cx = static_cast<std::uint32_t>(cells_x());
  const std::uint32_t i = c % cx, j = c / cx;
  // Even: (p00, p01, p11); odd: (p00, p11, p10), as (column offset, row offset).
  static constexpr std::array<std::array<std::array<std::uint32_t, 2>, 3>, 2> kOffsets = {
      {{{{0, 0}, {0, 1}, {1, 1}}}, {{{0, 0}, {1, 1}, {1, 0}}}}};
  const auto& o = kOffsets[t % 2][static_cast<std::size_t>(k)];
  return (j + o[1]) * static_cast<std::uint32_t>(samples_x) + i + o[0];
}

std::uint8_t HeightField::active_edges(std::uint32_t t, float cos_threshold) const noexcept {
  const std::uint32_t c = t / 2;
  const int cx = cells_x(), cz = cells_z();
  const int i = static_cast<int>(c % static_cast<std::uint32_t>(cx));
  const int j = static_cast<int>(c / static_cast<std::uint32_t>(cx));
  const bool even = t % 2 == 0;
  // The triangle across each edge k (see the mapping): even (p00, p01, p11) meets the odd
  // triangle of cell (i - 1, j) over edge 0, of cell (i, j + 1) over edge 1, and its own cell's
  // odd one over the diagonal; odd (p00, p11, p10) meets its own cell's even one over the
  // diagonal, the even triangle of cell (i + 1, j) over edge 1 and of cell (i, j - 1) over edge 2.
  const auto cell_index = [&](int ci, int cj) { return static_cast<std::uint32_t>(cj * cx + ci); };
  std::array<std::int64_t, 3> across{};
  const auto neighbour = [&](int ci, int cj, bool want_even) -> std::int64_t {
    if (ci < 0 || cj < 0 || ci >= cx || cj >= cz) return -1;
    const std::uint32_t cell = cell_index(ci, cj);
    if (is_hole(cell)) return -1;
    return static_cast<std::int64_t>(2 * cell + (want_even ? 0u : 1u));
  };
  if (even) {
    across = {neighbour(i - 1, j, false), neighbour(i, j + 1, false), static_cast<std::int64_t>(t + 1)};
  } else {
    across = {static_cast<std::int64_t>(t - 1), neighbour(i + 1, j, true), neighbour(i, j - 1, true)};
  }
  const std::array<Vec3, 3> p = grid_corners(t);
  const Vec3 n1 = triangle_normal(p[0], p[1], p[2]);
  std::uint8_t bits = 0;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t other = across[static_cast<std::size_t>(k)];
    if (other < 0) {  // the field's border or a hole: a boundary edge, active from both sides
      bits |= active_edge_bits(k, 3u);
      continue;
    }
    const std::array<Vec3, 3> q = grid_corners(static_cast<std::uint32_t>(other));
    const Vec3 e = p[static_cast<std::size_t>((k + 1) % 3)] - p[static_cast<std::size_t>(k)];
    // Every triangle faces up: the windings agree over every edge.
    bits |= active_edge_bits(k, active_edge_sides(n1, triangle_normal(q[0], q[1], q[2]), e, true, cos_threshold));
  }
  return bits;
}

Triangle HeightField::triangle(std::uint32_t t) const noexcept {
  const std::array<Vec3, 3> p = grid_corners(t);
  return Triangle{{origin + p[0], origin + p[1], origin + p[2]}};
}

namespace {

/// HeightField::query's walk, handing `visit` each triangle with its corners (grid space), so
/// that a caller who needs them does not find them again (grid_corners' division, three reads).
template <class Visit>
void query_triangles(const HeightField& f, const Aabb3& local_box, Visit&& visit) {
  const Vec3 origin = f.origin;
  const Vec2 spacing = f.spacing;
  const Aabb3 box{local_box.min - origin, local_box.max - origin};
  if (!(box.min.x <= static_cast<float>(f.cells_x()) * spacing.x && box.max.x >= 0.0f &&
        box.min.z <= static_cast<float>(f.cells_z()) * spacing.y && box.max.z >= 0.0f && box.min.y <= f.max_height &&
        box.max.y >= f.min_height)) {
    return;
  }
  // Cells whose squares the box's xz rectangle may touch, then each triangle's own box decides:
  // the cells holding its corners, widened by kCellRangeSlack (relative, in cells) so that a
  // box on a grid line takes both cells beside it, which its closed box touches, and so that
  // the rounding of the division and of the corners' coordinates (float(i) * size, within a
  // few parts in 1e7) never drops a cell whose triangles reach the box. (It was a whole cell on
  // each side: for the few cells a body's box covers, most of the cells walked.)
  auto cell_range = [](float lo, float hi, float size, int count) {
    const float u = lo / size, v = hi / size;
    const float a = std::floor(u - kCellRangeSlack * (std::abs(u) + 1.0f));
    const float b = std::floor(v + kCellRangeSlack * (std::abs(v) + 1.0f));
    return glm::ivec2(a < 0.0f ? 0 : a > static_cast<float>(count - 1) ? count - 1 : static_cast<int>(a),
                      b < 0.0f ? 0 : b > static_cast<float>(count - 1) ? count - 1 : static_cast<int>(b));
  };
  const glm::ivec2 is = cell_range(box.min.x, box.max.x, spacing.x, f.cells_x());
  const glm::ivec2 js = cell_range(box.min.z, box.max.z, spacing.y, f.cells_z());
  const int i0 = is.x, i1 = is.y, j0 = js.x, j1 = js.y;
  const int b = kHeightFieldBlockCells;
  for (int bz = j0 / b; bz <= j1 / b; ++bz) {
    for (int bx = i0 / b; bx <= i1 / b; ++bx) {
      const std::array<float, 2> range = f.block_range[static_cast<std::size_t>(bz) * f.blocks_x + bx];
      if (!(range[0] <= box.max.y && box.min.y <= range[1])) continue;
      for (int j = std::max(j0, bz * b); j <= std::min(j1, bz * b + b - 1); ++j) {
        for (int i = std::max(i0, bx * b); i <= std::min(i1, bx * b + b - 1); ++i) {
          const std::uint32_t c = static_cast<std::uint32_t>(j) * static_cast<std::uint32_t>(f.cells_x()) + static_cast<std::uint32_t>(i);
          if (f.is_hole(c)) continue;
          // The cell's four samples once, for both triangles.
          const std::array<std::array<Vec3, 3>, 2> corners = cell_triangles(f, i, j);
          // Each triangle's box: the diagonal p00 p11 is shared, and the third corner added.
          const Vec3 lo = glm::min(corners[0][0], corners[0][2]), hi = glm::max(corners[0][0], corners[0][2]);
          if (overlap(Aabb3{glm::min(lo, corners[0][1]), glm::max(hi, corners[0][1])}, box) && !visit(2 * c, corners[0])) return;
          if (overlap(Aabb3{glm::min(lo, corners[1][2]), glm::max(hi, corners[1][2])}, box) && !visit(2 * c + 1, corners[1])) return;
        }
      }
    }
  }
}

}  // namespace

void HeightField::query(const Aabb3& local_box, TriangleQueryCallback visit) const {
  query_triangles(*this, local_box, [&](std::uint32_t t, const std::array<Vec3, 3>&) { return visit(t); });
}

void HeightField::ray_cast(const Ray3& local_ray, TriangleRayCallback visit, float max_fraction) const {
  cast(*this, local_ray, max_fraction, [&](std::uint32_t t, float fraction, float max_t) {
    const float next = visit(t, fraction);
    return next < max_t ? next : max_t;  // (0 or less stops; NaN goes on unclipped)
  });
}

TriangleRayHit HeightField::ray_cast(const Ray3& local_ray, float max_fraction) const noexcept {
  TriangleRayHit hit;
  cast(*this, local_ray, max_fraction, [&](std::uint32_t t, float fraction, float max_t) {
    if (fraction < max_t || (hit.triangle == std::numeric_limits<std::uint32_t>::max() && fraction <= max_t)) {
      hit.triangle = t;
      hit.fraction = fraction;
      return fraction;
    }
    return max_t;
  });
  if (hit.triangle != std::numeric_limits<std::uint32_t>::max()) {
    const std::array<Vec3, 3> p = grid_corners(hit.triangle);
    hit.normal = triangle_normal(p[0], p[1], p[2]);
  }
  return hit;
}

HeightField make_height_field(int samples_x, int samples_z, std::span<const float> heights, Vec2 spacing, Vec3 origin,
                              std::span<const std::uint8_t> holes) {
  if (samples_x < 2 || samples_z < 2) {
    throw InvalidInput("height field: samples_x " + std::to_string(samples_x) + " and samples_z " + std::to_string(samples_z) +
                       ": need at least 2 x 2");
  }
  const std::size_t count = static_cast<std::size_t>(samples_x) * static_cast<std::size_t>(samples_z);
  const std::size_t cells = static_cast<std::size_t>(samples_x - 1) * static_cast<std::size_t>(samples_z - 1);
  if (2 * cells > kMaxMeshTriangles) {
    throw InvalidInput("height field: " + std::to_string(2 * cells) + " triangles, more than the " +
                       std::to_string(kMaxMeshTriangles) + " a mesh can name (kMaxMeshTriangles)");
  }
  if (heights.size() != count) {
    throw InvalidInput("height field heights: " + std::to_string(heights.size()) + " given, expected " + std::to_string(count) +
                       " (samples_x " + std::to_string(samples_x) + " * samples_z " + std::to_string(samples_z) + ")");
  }
  for (int a = 0; a < 2; ++a) {
    if (!(std::isfinite(spacing[a]) && spacing[a] > 0.0f)) {
      throw InvalidInput(std::string("height field spacing.") + (a == 0 ? "x" : "y") + ": must be finite and > 0 (got " +
                         std::to_string(spacing[a]) + ")");
    }
  }
  if (!is_finite(origin)) throw InvalidInput("height field origin: not finite");
  if (!std::isfinite(static_cast<float>(samples_x - 1) * spacing.x) || !std::isfinite(static_cast<float>(samples_z - 1) * spacing.y)) {
    throw InvalidInput("height field: extent beyond float range (samples times spacing)");
  }
  if (!holes.empty() && holes.size() != cells) {
    throw InvalidInput("height field holes: " + std::to_string(holes.size()) + " given, expected 0 or " + std::to_string(cells) +
                       " (one per cell: (samples_x - 1) * (samples_z - 1))");
  }
  HeightField f;
  f.samples_x = samples_x;
  f.samples_z = samples_z;
  f.spacing = spacing;
  f.origin = origin;
  f.heights.assign(heights.begin(), heights.end());
  f.min_height = kInfinity;
  f.max_height = -kInfinity;
  for (std::size_t k = 0; k < count; ++k) {
    if (!std::isfinite(heights[k])) {
      throw InvalidInput("height field height at row " + std::to_string(k / static_cast<std::size_t>(samples_x)) + ", column " +
                         std::to_string(k % static_cast<std::size_t>(samples_x)) + ": not finite");
    }
    f.min_height = std::min(f.min_height, heights[k]);
    f.max_height = std::max(f.max_height, heights[k]);
  }
  if (!std::isfinite(f.max_height - f.min_height)) throw InvalidInput("height field: heights span more than float range");
  if (std::any_of(holes.begin(), holes.end(), [](std::uint8_t h) { return h != 0; })) f.holes.assign(holes.begin(), holes.end());

  const int b = kHeightFieldBlockCells;
  f.blocks_x = (f.cells_x() + b - 1) / b;
  f.blocks_z = (f.cells_z() + b - 1) / b;
  f.block_range.assign(static_cast<std::size_t>(f.blocks_x) * static_cast<std::size_t>(f.blocks_z), {kInfinity, -kInfinity});
  for (int j = 0; j < f.cells_z(); ++j) {
    for (int i = 0; i < f.cells_x(); ++i) {
      if (f.is_hole(static_cast<std::uint32_t>(j) * static_cast<std::uint32_t>(f.cells_x()) + static_cast<std::uint32_t>(i))) continue;
      std::array<float, 2>& range = f.block_range[static_cast<std::size_t>(j / b) * f.blocks_x + i / b];
      for (int dj = 0; dj < 2; ++dj) {
        for (int di = 0; di < 2; ++di) {
          range[0] = std::min(range[0], f.height(i + di, j + dj));
          range[1] = std::max(range[1], f.height(i + di, j + dj));
        }
      }
    }
  }
  return f;
}

void for_each_triangle(const HeightField& field, const Transform3& xf, const Aabb3& box,
                       TriangleCornersCallback visit) {
  const Aabb3 local = transform_aabb(box, inv_mul(xf, Transform3{}));
  Transform3 grid_to_world = xf;
  grid_to_world.p += rotate(xf.q, field.origin);
  const Frame3 f = Frame3::from(grid_to_world);
  // A cell's two triangles share their diagonal p00 p11 (corners 0 and 2 of the even one,
  // 0 and 1 of the odd one): when both meet the box, as they mostly do, the odd one takes the
  // even one's transformed corners (the same values) instead of transforming them again.
  std::uint32_t even = 1;  // the last even triangle transformed (never odd: none yet)
  Vec3 w00{0.0f}, w11{0.0f};
  query_triangles(field, local, [&](std::uint32_t t, const std::array<Vec3, 3>& c) -> bool {
    if ((t & 1u) == 0u) {
      even = t;
      w00 = transform_point(f, c[0]);
      w11 = transform_point(f, c[2]);
      return visit(t, {w00, transform_point(f, c[1]), w11});
    }
    if (t == even + 1u) return visit(t, {w00, w11, transform_point(f, c[2])});
    return visit(t, {transform_point(f, c[0]), transform_point(f, c[1]), transform_point(f, c[2])});
  });
}

Aabb3 compute_aabb(const HeightField& field, const Transform3& xf) noexcept {
  const Vec3 lo = field.origin + Vec3(0.0f, field.min_height, 0.0f);
  const Vec3 hi = field.origin + Vec3(static_cast<float>(field.cells_x()) * field.spacing.x, field.max_height,
                                      static_cast<float>(field.cells_z()) * field.spacing.y);
  return transform_aabb({lo, hi}, xf);
}

}  // namespace collide
