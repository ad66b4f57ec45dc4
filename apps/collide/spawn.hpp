#pragma once
// Spawning bodies in free space, 2D and 3D: is a place free of statics and of the bodies placed so
// far? Statics through the world's static tree; bodies through a dynamic AABB tree of their own
// that grows by one leaf per placed piece (the world's body broad phase is only rebuilt by a step,
// so asking the world after each add_body scanned every body: spawning was O(N^2)). O(log N) per
// try: a million bodies spawn in seconds.

#include <collide/broad/dynamic_tree.hpp>
#include <collide/core/large_pages.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/world/world.hpp>

#include <span>
#include <utility>
#include <vector>

namespace collide::cli {

/// Tries in a row that find no free place, after which a spawner stops: the space is full. At a
/// microsecond or two per try, a full map gives up within a few tens of milliseconds.
inline constexpr int kSpawnMissesInARow = 1000;

/// The free space of a world for spawning: the world's statics (sensors excluded: bodies may
/// start inside a sensor) and its bodies, plus every body added here since.
template <int D>
class SpawnSpace {
 public:
  using Shape = BodyShapeN<D>;
  using Xf = TransformN<D>;

  /// Takes in the bodies the world already has (a scene file's own bodies).
  explicit SpawnSpace(const WorldN<D>& world) : world_(world), tree_({0.0f, 0.0f}) {
    for (const BodyId id : world.body_ids()) add(id);
  }

  /// True when `shapes` placed by `xf` touch no solid static and no body. "Touch" is what the
  /// world's own spawning queries always meant: 2D `overlap`, 3D a touching `contact`.
  [[nodiscard]] bool fits(std::span<const Shape> shapes, const Xf& xf) const {
    for (const Shape& shape : shapes) {
      const AabbN<D> box = compute_aabb(shape, xf);
      if (touches_static(shape, xf, box)) return false;
      bool clear = true;
      tree_.query(box, [&](int id) {
        const auto& [body, piece] = pieces_[static_cast<std::size_t>(id)];
        clear = !touches(shape, xf, world_.shapes(body)[piece], world_.transform(body));
        return clear;
      });
      if (!clear) return false;
    }
    return true;
  }

  /// Takes in a body just added to the world (its shapes are read from there, not copied: a 2D
  /// polygon holds 64 vertex slots).
  void add(BodyId id) {
    const std::span<const Shape> shapes = world_.shapes(id);
    const Xf& xf = world_.transform(id);
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      tree_.insert(compute_aabb(shapes[k], xf));
      pieces_.emplace_back(id, k);
    }
  }

 private:
  static bool touches(const Shape& a, const Xf& xa, const Shape& b, const Xf& xb) {
    if constexpr (D == 2) {
      return overlap(a, xa, b, xb);
    } else {
      return contact(a, xa, b, xb).touching();
    }
  }

  bool touches_static(const Shape& shape, const Xf& xf, [[maybe_unused]] const AabbN<D>& box) const {
    bool hit = false;
    const QueryFilter statics{.bodies = false};
    if constexpr (D == 2) {
      world_.query_aabb(box, statics, [&](const ColliderRef& c) {
        hit = overlap(shape, xf, world_.collider_shape(c), world_.collider_transform(c));
        return !hit;
      });
    } else {  // (collide_shape computes the same box itself)
      world_.collide_shape(shape, xf, statics, [&](const ColliderRef&, const ManifoldN<D>&) {
        hit = true;
        return false;
      });
    }
    return hit;
  }

  const WorldN<D>& world_;
  DynamicTreeN<D> tree_;
  LargePageVector<std::pair<BodyId, std::size_t>> pieces_;  // (body, piece) by tree id; 16 MB at 1e6
};

}  // namespace collide::cli
