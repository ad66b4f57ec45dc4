// The world's independent end-of-step check, 2D and 3D: no body may end a step inside static
// geometry or cross a level's surface during it (tunnelling), or end outside the world's
// bounds. It uses its own uniform grid over the static pieces and the level shapes' triangles
// and the exact contact (or ray cast) of every nearby pair, so a bug in the world's tree, the
// levels' BVHs, the early-out chains or the continuous collision cannot hide a body that went
// through a wall or a floor.

#include "world_impl.hpp"

#include <collide/ccd/raycast.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/contact.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace collide {

namespace {

/// Smallest range of bodies one task checks.
constexpr int kCheckBodiesPerTask = 128;

/// A static item covering more cells than this is tested against every body instead.
constexpr std::int64_t kMaxCheckCellsPerPiece = 4096;

/// Index of the cell holding coordinate x, clamped far inside int range.
std::int32_t cell_of(float x, float cell) {
  const double c = std::floor(static_cast<double>(x) / cell);
  return static_cast<std::int32_t>(std::clamp(c, -1.0e9, 1.0e9));
}

/// The cell range of a box and its key: 2D keys pack two 32-bit cell indices, 3D keys three
/// 21-bit ones (cells beyond +-2^20 share keys: more candidates, never fewer).
template <int D>
struct CellRange {
  std::array<std::int32_t, D> lo;
  std::array<std::int32_t, D> hi;

  CellRange(const AabbN<D>& box, float cell) {
    for (int k = 0; k < D; ++k) {
      lo[k] = cell_of(box.min[k], cell);
      hi[k] = cell_of(box.max[k], cell);
    }
  }
  [[nodiscard]] std::int64_t count() const {
    std::int64_t n = 1;
    for (int k = 0; k < D; ++k) n *= std::int64_t{hi[k] - lo[k] + 1};
    return n;
  }
  static std::uint64_t key(const std::array<std::int32_t, D>& c) {
    if constexpr (D == 2) {
      return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c[0])) << 32) |
             static_cast<std::uint32_t>(c[1]);
    } else {
      const auto part = [](std::int32_t v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v) & 0x1fffffu); };
      return (part(c[0]) << 42) | (part(c[1]) << 21) | part(c[2]);
    }
  }
  template <class Visit>
  void for_each(Visit&& visit) const {
    std::array<std::int32_t, D> c = lo;
    for (;;) {
      visit(key(c));
      int k = 0;
      for (; k < D; ++k) {
        if (c[k] < hi[k]) {
          ++c[k];
          break;
        }
        c[k] = lo[k];
      }
      if (k == D) return;
    }
  }
};

constexpr std::uint64_t kOversizedKey = ~std::uint64_t{0};

}  // namespace

template <int D>
void WorldN<D>::Impl::check(StepStats& stats) {
  detail::CheckGridN<D>& grid = check_grid;
  const auto piece_items = static_cast<std::uint32_t>(static_pieces.size());
  if (check_grid_dirty) {
    grid.cells.clear();
    grid.triangles.clear();
    grid.triangle_piece.clear();
    // Items: the convex static pieces, and each triangle of the level shapes.
    std::vector<AabbN<D>> boxes;
    std::vector<std::uint32_t> items;
    for (std::uint32_t i = 0; i < piece_items; ++i) {
      const StaticPiece& sp = static_pieces[i];
      if (statics[sp.owner].sensor) continue;
      if constexpr (D == 3) {
        if (sp.level) {
          const StaticDefN<D>& st = statics[sp.owner];
          const auto add = [&](std::uint32_t, const std::array<Vec3, 3>& c) -> bool {
            items.push_back(piece_items + static_cast<std::uint32_t>(grid.triangles.size()));
            boxes.push_back({glm::min(glm::min(c[0], c[1]), c[2]), glm::max(glm::max(c[0], c[1]), c[2])});
            grid.triangles.push_back(c);
            grid.triangle_piece.push_back(i);
            return true;
          };
          std::visit(
              [&](const auto& s) {
                using S = std::decay_t<decltype(s)>;
                if constexpr (detail::kIsMesh<S> || detail::kIsField<S>) {
                  for_each_triangle(*s, st.transform, sp.box, add);
                }
              },
              st.shapes[sp.piece]);
          continue;
        }
      }
      items.push_back(i);
      boxes.push_back(sp.box);
    }
    std::vector<float> sides;
    for (const AabbN<D>& b : boxes) {
      const VecN<D> s = b.max - b.min;
      float side = 0.0f;
      for (int k = 0; k < D; ++k) side = std::max(side, s[k]);
      sides.push_back(side);
    }
    if (!sides.empty()) {
      std::nth_element(sides.begin(), sides.begin() + static_cast<std::ptrdiff_t>(sides.size() / 2), sides.end());
      grid.cell = std::max(2.0f * sides[sides.size() / 2], 1e-3f);
    }
    for (std::size_t n = 0; n < items.size(); ++n) {
      const CellRange<D> range(boxes[n], grid.cell);
      if (range.count() > kMaxCheckCellsPerPiece) {
        grid.cells[kOversizedKey].push_back(items[n]);
        continue;
      }
      range.for_each([&](std::uint64_t key) { grid.cells[key].push_back(items[n]); });
    }
    grid.items = piece_items + static_cast<std::uint32_t>(grid.triangles.size());
    ++grid.version;
    check_grid_dirty = false;
  }
  parallel(static_cast<int>(bodies.size()), kCheckBodiesPerTask, [&](int begin, int end, int w) {
    for (int i = begin; i < end; ++i) check_body(static_cast<std::uint32_t>(i), w);
  });
  collect_workers(stats);
}

template <int D>
void WorldN<D>::Impl::check_body(std::uint32_t i, int w) {
  const detail::CheckGridN<D>& grid = check_grid;
  detail::StepWorkerN<D>& wk = workers[static_cast<std::size_t>(w)];
  StepStats& stats = wk.stats;
  const auto piece_items = static_cast<std::uint32_t>(static_pieces.size());
  if (wk.check_grid_version != grid.version) {
    wk.check_stamp.assign(grid.items, 0);
    wk.check_query = 0;
    wk.check_grid_version = grid.version;
  }
  const auto oversized = grid.cells.find(kOversizedKey);
  // Each item whose cells meet `box` once (stamped per query), or every item for a huge box.
  const auto for_items = [&](const AabbN<D>& box, auto&& test) {
    if (++wk.check_query == 0) {  // wrapped: old stamps could match again
      std::fill(wk.check_stamp.begin(), wk.check_stamp.end(), 0u);
      wk.check_query = 1;
    }
    const std::uint32_t query = wk.check_query;
    const auto once = [&](std::uint32_t id) {
      if (wk.check_stamp[id] == query) return;
      wk.check_stamp[id] = query;
      test(id);
    };
    const CellRange<D> range(box, grid.cell);
    if (range.count() > kMaxCheckCellsPerPiece) {
      for (const auto& [key, ids] : grid.cells) {
        for (const std::uint32_t id : ids) once(id);
      }
      return;
    }
    range.for_each([&](std::uint64_t key) {
      const auto it = grid.cells.find(key);
      if (it == grid.cells.end()) return;
      for (const std::uint32_t id : it->second) once(id);
    });
    if (oversized != grid.cells.end()) {
      for (const std::uint32_t id : oversized->second) once(id);
    }
  };
  {
    const Body& b = bodies[i];
    if (!b.alive || b.sensor) return;
    if (options.bounds && !collide::contains(*options.bounds, transform_point(b.xf, b.local_center))) {
      ++stats.escaped;
    }
    bool inside = false;
    float magnitude = std::fabs(b.xf.p[0]);
    for (int a = 1; a < D; ++a) magnitude += std::fabs(b.xf.p[a]);
    magnitude += b.bounding_radius;
    for (std::size_t k = 0; k < b.shapes.size(); ++k) {
      const AabbN<D> box = piece_box(b, static_cast<int>(k));
      const detail::PieceInfoN<D>& piece = b.pieces[k];
      const float tolerance = kTunnelDepthFraction * std::max(piece.inner_size, 0.1f * piece.radius) +
                              kRelativeTolerance * magnitude;
      for_items(box, [&](std::uint32_t id) {
        float depth = 0.0f;
        if (id < piece_items) {
          const StaticPiece& sp = static_pieces[id];
          if (!overlap(box, sp.box)) return;
          const StaticDefN<D>& st = statics[sp.owner];
          if (!should_collide(b.filter, st.filter)) return;
          depth = detail::piece_depth(b.shapes[k], b.xf, static_piece(sp.owner, sp.piece), st.transform);
        } else if constexpr (D == 3) {
          const std::array<Vec3, 3>& c = grid.triangles[id - piece_items];
          const StaticDefN<D>& st = statics[static_pieces[grid.triangle_piece[id - piece_items]].owner];
          if (!should_collide(b.filter, st.filter)) return;
          const detail::PlacedTriangle t = detail::placed_triangle(c);
          depth = std::visit([&](const auto& s) { return collide::contact(s, b.xf, t.shape, t.xf); },
                             b.shapes[k])
                      .max_depth();
        }
        stats.max_static_depth = std::max(stats.max_static_depth, depth);
        inside = inside || depth > tolerance;
      });
    }
    // A level is a surface, not a solid: a body through a floor ends below it, not in it. Its
    // centre's path over the step crossing a triangle counts as tunnelling.
    if constexpr (D == 3) {
      for (int leg = 0; leg + 1 < b.path_count && !inside; ++leg) {
        const Ray3 ray{b.path[leg], b.path[leg + 1] - b.path[leg]};
        if (ray.translation == Vec3(0.0f)) continue;
        const Aabb3 box{glm::min(b.path[leg], b.path[leg + 1]), glm::max(b.path[leg], b.path[leg + 1])};
        for_items(box, [&](std::uint32_t id) {
          if (id < piece_items || inside) return;
          const std::array<Vec3, 3>& c = grid.triangles[id - piece_items];
          const StaticDefN<D>& st = statics[static_pieces[grid.triangle_piece[id - piece_items]].owner];
          if (!should_collide(b.filter, st.filter)) return;
          inside = collide::raycast(Triangle{c}, Transform3{}, ray).hit;
        });
      }
    }
    if (inside) ++stats.tunnelled;
  }
}

template void WorldN<2>::Impl::check(StepStats&);
template void WorldN<3>::Impl::check(StepStats&);

}  // namespace collide
