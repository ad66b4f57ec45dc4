#pragma once
/// @file
/// The separating axis test for convex polygons (the lesson's "Separating Axis"): two convex
/// polygons are apart iff the perpendicular of some edge of one of them separates them.

#include <collide/shape/polygon.hpp>
#include <limits>
#include <span>

namespace collide {

/// The edge normal of A that separates A from B the most.
struct EdgeSeparation {
  int edge = 0;  ///< edge index on the first polygon
  /// Largest separation along that edge's outward normal: > 0 means a separating axis was found
  /// (the cores are that far apart along it); <= 0 is minus the overlap along the least
  /// penetrated axis of this polygon. World units.
  float separation = 0.0f;
  /// Vertex of the second polygon deepest along the axis (its support point in the direction
  /// of minus the edge normal): the incident edge is one of its two edges.
  int support = 0;
};

/// Over A's edge normals, the axis of greatest separation of B's core from A's core, with B
/// given in A's local frame by `b_in_a` (use inv_mul(xa, xb)). Works for the 2-vertex polygons
/// that stand for capsules and segments too. O(n m), four edges of A at a time.
/// Ericson, Real-Time Collision Detection, 5.2.1; Catto GDC 2007.
[[nodiscard]] EdgeSeparation find_max_separation(const Polygon& a, const Polygon& b,
                                                 const Transform& b_in_a) noexcept;

/// The separation of B's core from A's core along each of A's edge normals, B given in A's
/// local frame by `b_in_a`: out[i] = min_j n_i . (b_j - a_i), world units (> 0: that axis
/// separates them by that much; the largest is find_max_separation's). Frame-independent
/// values, computed relative to A's vertex 0 so large coordinates cancel first; four edges at
/// a time in registers for polygons of up to 8 vertices. `out` must hold at least a.count
/// values. Ericson, Real-Time Collision Detection, 5.2.1.
void edge_separations(const Polygon& a, const Polygon& b, const Transform& b_in_a,
                      std::span<float> out) noexcept;

/// The same test on raw arrays already in one frame: edge i of polygon 1 starts at
/// `vertices1[i]` and has unit outward normal `normals1[i]`; `vertices2` are the other polygon's
/// core vertices. Returns once an axis separates by more than `early_exit` (checked after each
/// group of four edges; then `separation` > `early_exit` but may not be the largest); pass the
/// radius sum to stop at an axis that proves the rounded shapes apart. The spans must have
/// sizes 1..kMaxPolygonVertices (the first two equal). `contact` uses the same test on x/y
/// arrays it builds once in A's frame.
[[nodiscard]] EdgeSeparation find_max_separation(
    std::span<const Vec2> vertices1, std::span<const Vec2> normals1,
    std::span<const Vec2> vertices2,
    float early_exit = std::numeric_limits<float>::infinity()) noexcept;

}  // namespace collide
