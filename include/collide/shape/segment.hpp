#pragma once
/// @file
/// A line segment in local space (a wall, a one-way platform, a link of a Tiled polyline).

#include <collide/core/aabb.hpp>
#include <collide/core/transform.hpp>

namespace collide {

/// The segment from `a` to `b`, zero thickness. Local space. As a 2-sided shape it has two
/// edges: edge 0 runs a -> b (outward normal to its right), edge 1 runs b -> a.
struct Segment {
  Vec2 a{0.0f, 0.0f};  ///< local space
  Vec2 b{0.0f, 0.0f};  ///< local space
};

/// A validated segment. Throws InvalidInput if a coordinate is not finite or a and b coincide
/// (or lie so close, about 1e-19, that their squared distance underflows float).
[[nodiscard]] Segment make_segment(Vec2 a, Vec2 b);

/// Bounding box of the segment placed by `xf`, world space.
[[nodiscard]] Aabb compute_aabb(const Segment& segment, const Transform& xf) noexcept;

}  // namespace collide
