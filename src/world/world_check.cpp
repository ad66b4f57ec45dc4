// The independent end-of-step check of World2D: no body may end a step inside static geometry
// (tunnelling) or outside the world's bounds. It uses its own uniform grid over the statics and
// the exact contact of every nearby pair, so a bug in the world's tree, its early-out chains or
// its continuous collision cannot hide a body that went through a wall.

#include "world_impl.hpp"

#include <collide/core/tolerance.hpp>
#include <collide/narrow/contact.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace collide {

namespace {

/// A static piece covering more cells than this is tested against every body instead.
constexpr std::int64_t kMaxCheckCellsPerPiece = 4096;

/// Index of the cell holding coordinate x, clamped far inside int range.
std::int32_t cell_of(float x, float cell) {
  const double c = std::floor(static_cast<double>(x) / cell);
  return static_cast<std::int32_t>(std::clamp(c, -1.0e9, 1.0e9));
}

std::uint64_t cell_key(std::int32_t x, std::int32_t y) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32) |
         static_cast<std::uint32_t>(y);
}

constexpr std::uint64_t kOversizedKey = ~std::uint64_t{0};

}  // namespace

void World2D::Impl::check(StepStats& stats) {
  detail::CheckGrid& grid = check_grid;
  if (check_grid_dirty) {
    grid.cells.clear();
    std::vector<float> sides;
    for (const detail::StaticPiece& sp : static_pieces) {
      const Vec2 s = sp.box.size();
      sides.push_back(std::max(s.x, s.y));
    }
    if (!sides.empty()) {
      std::nth_element(sides.begin(), sides.begin() + static_cast<std::ptrdiff_t>(sides.size() / 2), sides.end());
      grid.cell = std::max(2.0f * sides[sides.size() / 2], 1e-3f);
    }
    for (std::uint32_t i = 0; i < static_pieces.size(); ++i) {
      const detail::StaticPiece& sp = static_pieces[i];
      if (statics[sp.owner].sensor) continue;
      const std::int32_t x0 = cell_of(sp.box.min.x, grid.cell), x1 = cell_of(sp.box.max.x, grid.cell);
      const std::int32_t y0 = cell_of(sp.box.min.y, grid.cell), y1 = cell_of(sp.box.max.y, grid.cell);
      if (std::int64_t{x1 - x0 + 1} * (y1 - y0 + 1) > kMaxCheckCellsPerPiece) {
        grid.cells[kOversizedKey].push_back(i);
        continue;
      }
      for (std::int32_t y = y0; y <= y1; ++y) {
        for (std::int32_t x = x0; x <= x1; ++x) grid.cells[cell_key(x, y)].push_back(i);
      }
    }
    grid.stamp.assign(static_pieces.size(), 0);
    grid.query = 0;
    check_grid_dirty = false;
  }
  const auto oversized = grid.cells.find(kOversizedKey);
  for (std::uint32_t i = 0; i < bodies.size(); ++i) {
    const detail::Body& b = bodies[i];
    if (!b.alive || b.sensor) continue;
    if (options.bounds && !collide::contains(*options.bounds, transform_point(b.xf, b.local_center))) {
      ++stats.escaped;
    }
    bool inside = false;
    for (std::size_t k = 0; k < b.shapes.size(); ++k) {
      const Aabb box = piece_box(b, static_cast<int>(k));
      const detail::PieceInfo& piece = b.pieces[k];
      const float magnitude = std::fabs(b.xf.p.x) + std::fabs(b.xf.p.y) + b.bounding_radius;
      const float tolerance =
          kTunnelDepthFraction * std::max(piece.inner_size, 0.1f * piece.circle_radius) +
          kRelativeTolerance * magnitude;
      ++grid.query;
      const auto test = [&](std::uint32_t id) {
        if (grid.stamp[id] == grid.query) return;
        grid.stamp[id] = grid.query;
        const detail::StaticPiece& sp = static_pieces[id];
        if (!overlap(box, sp.box)) return;
        const StaticDef& st = statics[sp.owner];
        if (!should_collide(b.filter, st.filter)) return;
        const float depth =
            contact(b.shapes[k], b.xf, st.shapes[sp.piece], st.transform).max_depth();
        stats.max_static_depth = std::max(stats.max_static_depth, depth);
        inside = inside || depth > tolerance;
      };
      const std::int32_t x0 = cell_of(box.min.x, grid.cell), x1 = cell_of(box.max.x, grid.cell);
      const std::int32_t y0 = cell_of(box.min.y, grid.cell), y1 = cell_of(box.max.y, grid.cell);
      if (std::int64_t{x1 - x0 + 1} * (y1 - y0 + 1) > kMaxCheckCellsPerPiece) {
        for (std::uint32_t id = 0; id < static_pieces.size(); ++id) {  // a huge body: every static
          if (!statics[static_pieces[id].owner].sensor) test(id);
        }
      } else {
        for (std::int32_t y = y0; y <= y1; ++y) {
          for (std::int32_t x = x0; x <= x1; ++x) {
            const auto it = grid.cells.find(cell_key(x, y));
            if (it == grid.cells.end()) continue;
            for (const std::uint32_t id : it->second) test(id);
          }
        }
        if (oversized != grid.cells.end()) {
          for (const std::uint32_t id : oversized->second) test(id);
        }
      }
    }
    if (inside) ++stats.tunnelled;
  }
}

}  // namespace collide
