#pragma once
/// @file
/// Explicit Minkowski sum and difference of convex polygons (the lesson's "Minkowski Sum"):
/// A + B = {a + b}, A - B = {a - b}. A and B overlap iff A - B contains the origin, and the
/// closest point of A - B to the origin is the difference of A's and B's closest points. For
/// pictures, debugging and simple checks; GJK answers the same questions without building it.

#include <collide/shape/polygon.hpp>

#include <vector>

namespace collide {

/// A convex polygon of any vertex count, counter-clockwise, world space, grown by `radius`.
struct MinkowskiPolygon {
  std::vector<Vec2> vertices;  ///< counter-clockwise, no repeated or collinear vertices
  float radius = 0.0f;         ///< rounding radius: the sum of the inputs' radii

  /// Signed distance from the origin to the (rounded) polygon, world units: negative inside.
  /// Inside: the largest edge separation; outside: the distance to the nearest edge segment
  /// (Ericson 5.1.2); then minus `radius`. O(n).
  [[nodiscard]] float signed_distance_to_origin() const noexcept;
  /// True when the origin lies in the closed (rounded) polygon.
  [[nodiscard]] bool contains_origin() const noexcept {
    return signed_distance_to_origin() <= 0.0f;
  }
};

/// The Minkowski sum of A placed by `xa` and B placed by `xb`, world space, exact, in O(n + m)
/// by merging the two edge sequences by angle (de Berg et al., Computational Geometry, 13.3).
/// Edges parallel within kParallelTolerance are merged into one. Edge directions are taken
/// from the rotated local vertices, before the translation is added, so the merge decisions
/// keep full precision far from the world origin. Allocates the result (this is the explicit,
/// readable path for pictures and checks; GJK answers the same questions without it).
[[nodiscard]] MinkowskiPolygon minkowski_sum(const Polygon& a, const Transform& xa,
                                             const Polygon& b, const Transform& xb);

/// The Minkowski difference A - B = A + (-B), world space, O(n + m) (negating B is a half
/// turn, so it stays counter-clockwise). Its `signed_distance_to_origin` is the signed
/// distance between A and B: the gap when apart, minus the penetration depth when overlapping.
[[nodiscard]] MinkowskiPolygon minkowski_difference(const Polygon& a, const Transform& xa,
                                                    const Polygon& b, const Transform& xb);

}  // namespace collide
