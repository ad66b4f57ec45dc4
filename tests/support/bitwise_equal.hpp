#pragma once
// Bit-for-bit comparisons, for tests that hold a fast path to the path it promises to equal
// (the small-polygon front end, the batched polygon-circle contact, raycast_fraction).

#include <collide/ccd/raycast.hpp>
#include <collide/narrow/manifold.hpp>

#include <bit>
#include <cstdint>
#include <cstring>

namespace collide::test {

/// True when `m` and `expected` have the same count and the same bits in the normal and in
/// every valid point's position, depth and feature ids.
inline bool bitwise_equal(const Manifold& m, const Manifold& expected) {
  if (m.count != expected.count) return false;
  if (std::memcmp(&m.normal, &expected.normal, sizeof(Vec2)) != 0) return false;
  for (int i = 0; i < m.count; ++i) {
    const ManifoldPoint& p = m.points[static_cast<std::size_t>(i)];
    const ManifoldPoint& q = expected.points[static_cast<std::size_t>(i)];
    if (std::memcmp(&p.point, &q.point, sizeof(Vec2)) != 0 ||
        std::memcmp(&p.depth, &q.depth, sizeof(float)) != 0 || !(p.id == q.id)) {
      return false;
    }
  }
  return true;
}

/// True when `f` has the hit and the bits of the fraction of `expected` (raycast_fraction's
/// promise to equal raycast).
template <int D>
bool bitwise_equal(const RayFraction& f, const RayHitN<D>& expected) {
  return f.hit == expected.hit && std::bit_cast<std::uint32_t>(f.fraction) == std::bit_cast<std::uint32_t>(expected.fraction);
}

}  // namespace collide::test
