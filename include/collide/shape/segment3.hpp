#pragma once
/// @file
/// A 3D line segment in local space (a laser's path kept as a shape, a thin rod, a rope link).

#include <collide/core/aabb.hpp>
#include <collide/core/transform3.hpp>

namespace collide {

/// The segment from `a` to `b`, zero thickness. Local space. Features: vertex 0 (a), vertex 1
/// (b), edge 0.
struct Segment3 {
  Vec3 a{0.0f, 0.0f, 0.0f};  ///< local space
  Vec3 b{0.0f, 0.0f, 0.0f};  ///< local space
};

/// A validated segment. Throws InvalidInput if a coordinate is not finite or a and b coincide
/// (or lie so close, about 1e-19, that their squared distance underflows float).
[[nodiscard]] Segment3 make_segment(Vec3 a, Vec3 b);

/// Bounding box of the segment placed by `xf`, world space.
[[nodiscard]] Aabb3 compute_aabb(const Segment3& segment, const Transform3& xf) noexcept;

}  // namespace collide
