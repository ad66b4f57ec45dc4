#pragma once
/// @file
/// The separating axis test for convex polygons (the lesson's "Separating Axis"): two convex
/// polygons are apart iff the perpendicular of some edge of one of them separates them.

#include <collide/shape/polygon.hpp>

namespace collide {

/// The edge normal of A that separates A from B the most.
struct EdgeSeparation {
  int edge = 0;  ///< edge index on the first polygon
  /// Largest separation along that edge's outward normal: > 0 means a separating axis was found
  /// (the cores are that far apart along it); <= 0 is minus the overlap along the least
  /// penetrated axis of this polygon. World units.
  float separation = 0.0f;
};

/// Over A's edge normals, the axis of greatest separation of B's core from A's core, with B
/// given in A's local frame by `b_in_a` (use inv_mul(xa, xb)). O(n m).
/// Ericson, Real-Time Collision Detection, 5.2.1; Catto GDC 2007.
[[nodiscard]] EdgeSeparation find_max_separation(const Polygon& a, const Polygon& b,
                                                 const Transform& b_in_a) noexcept;

}  // namespace collide
