#pragma once
// Boxes too big for a grid (they would cover more cells than a grid allows per box) are kept
// in a side list and tested against everything: the same few loops for every grid.

#include <collide/broad/broad_phase.hpp>

#include <cstdint>
#include <span>

namespace collide::detail {

/// Pairs of an oversized box with any other box, each once: (o, j) for every j, except that a
/// pair of two oversized boxes is reported only from the smaller id.
template <int D>
void oversized_pairs(std::span<const int> oversized, std::span<const std::uint8_t> is_oversized,
                     std::span<const AabbN<D>> boxes, PairList& pairs) {
  const int n = static_cast<int>(boxes.size());
  for (const int o : oversized) {
    const AabbN<D> big = boxes[o];
    for (int j = 0; j < n; ++j) {
      if (j == o || (is_oversized[j] && j < o)) continue;
      if (overlap(big, boxes[j])) pairs.emplace_back(o < j ? o : j, o < j ? j : o);
    }
  }
}

/// The oversized boxes overlapping `box`; false when the callback stopped the query.
template <int D>
bool oversized_query(std::span<const int> oversized, std::span<const AabbN<D>> boxes,
                     const AabbN<D>& box, QueryCallback callback) {
  for (const int o : oversized) {
    if (overlap(boxes[o], box) && !callback(o)) return false;
  }
  return true;
}

/// The oversized boxes the ray (prepared as `slab`) meets; returns the ray's max fraction
/// after clipping.
template <int D>
float oversized_ray_cast(std::span<const int> oversized, std::span<const AabbN<D>> boxes,
                         const SlabRayN<D>& slab, float limit, RayCallback callback) {
  for (const int o : oversized) {
    if (limit <= 0.0f) break;
    if (slab.fraction(boxes[o], limit) < 0.0f) continue;
    const float r = callback(o, limit);
    if (r < limit) limit = r;
  }
  return limit;
}

}  // namespace collide::detail
