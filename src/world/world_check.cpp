// The world's independent end-of-step check, 2D and 3D: no body may end a step inside static
// geometry or cross a level's surface during it (tunnelling), or end outside the world's
// bounds. It uses its own hashed uniform grid over the static pieces and the level shapes' triangles
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

}  // namespace

template <int D>
void WorldN<D>::Impl::check(StepStats& stats) {
  detail::CheckGridN<D>& grid = check_grid;
  const auto piece_items = static_cast<std::uint32_t>(static_pieces.size());
  if (check_grid_dirty) {
    grid.items.clear();
    grid.triangles.clear();
    grid.triangle_piece.clear();
    // Items: the convex static pieces, and each triangle of the level shapes.
    LargePageVector<AabbN<D>> boxes;
    for (std::uint32_t i = 0; i < piece_items; ++i) {
      const StaticPiece& sp = static_pieces[i];
      if (statics[sp.owner].sensor) continue;
      if constexpr (D == 3) {
        if (sp.level) {
          const StaticDefN<D>& st = statics[sp.owner];
          const auto add = [&](std::uint32_t, const std::array<Vec3, 3>& c) -> bool {
            grid.items.push_back(piece_items + static_cast<std::uint32_t>(grid.triangles.size()));
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
      grid.items.push_back(i);
      boxes.push_back(sp.box);
    }
    grid.grid.build(boxes);  // cells of twice the median item size
    check_grid_dirty = false;
  }
  parallel(static_cast<int>(bodies.size()), kCheckBodiesPerTask, [&](int begin, int end, int w) {
    for (int i = begin; i < end; ++i) {
      // The shapes and further pieces of a body a few ahead (in the shape pool and a heap block,
      // apart from the body).
      detail::prefetch_shapes_ahead(bodies, i, end);
      check_body(static_cast<std::uint32_t>(i), w);
    }
  });
  collect_workers(stats);
}

template <int D>
void WorldN<D>::Impl::check_body(std::uint32_t i, int w) {
  const detail::CheckGridN<D>& grid = check_grid;
  detail::StepWorkerN<D>& wk = workers[static_cast<std::size_t>(w)];
  StepStats& stats = wk.stats;
  const auto piece_items = static_cast<std::uint32_t>(static_pieces.size());
  // Each item whose box meets `box`, once.
  const auto for_items = [&](const AabbN<D>& box, auto&& test) {
    grid.grid.query(box, [&](int n) {
      test(grid.items[static_cast<std::size_t>(n)]);
      return true;
    });
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
      const detail::PieceInfoN<D>& piece = b.piece(k).info;
      const float tolerance = kTunnelDepthFraction * std::max(piece.inner_size, 0.1f * piece.radius) +
                              kRelativeTolerance * magnitude;
      for_items(box, [&](std::uint32_t id) {
        float depth = 0.0f;
        if (id < piece_items) {
          const StaticPiece& sp = static_pieces[id];
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
        // The grid's cells along the leg (3D-DDA), not every cell of the leg's box: a bullet's
        // leg crosses hundreds of cells of its box.
        grid.grid.ray_cast(ray, [&](int n, float max_fraction) {
          const std::uint32_t id = grid.items[static_cast<std::size_t>(n)];
          if (id < piece_items) return max_fraction;
          const std::array<Vec3, 3>& c = grid.triangles[id - piece_items];
          const StaticDefN<D>& st = statics[static_pieces[grid.triangle_piece[id - piece_items]].owner];
          if (!should_collide(b.filter, st.filter)) return max_fraction;
          inside = collide::raycast(Triangle{c}, Transform3{}, ray).hit;
          return inside ? 0.0f : max_fraction;  // one crossing is enough
        });
      }
    }
    if (inside) ++stats.tunnelled;
  }
}

template void WorldN<2>::Impl::check(StepStats&);
template void WorldN<3>::Impl::check(StepStats&);

}  // namespace collide
