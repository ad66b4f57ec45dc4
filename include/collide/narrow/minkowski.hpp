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

  /// Signed distance from the origin to the (rounded) polygon: negative inside. O(n).
  [[nodiscard]] float signed_distance_to_origin() const noexcept;
  /// True when the origin lies in the closed (rounded) polygon.
  [[nodiscard]] bool contains_origin() const noexcept {
    return signed_distance_to_origin() <= 0.0f;
  }
};

/// The Minkowski sum of A placed by `xa` and B placed by `xb`, world space, exact, in O(n + m)
/// by merging the two edge sequences by angle (de Berg et al., Computational Geometry, 13.3).
/// Collinear edges are merged.
[[nodiscard]] MinkowskiPolygon minkowski_sum(const Polygon& a, const Transform& xa,
                                             const Polygon& b, const Transform& xb);

/// The Minkowski difference A - B = A + (-B), world space, O(n + m).
[[nodiscard]] MinkowskiPolygon minkowski_difference(const Polygon& a, const Transform& xa,
                                                    const Polygon& b, const Transform& xb);

}  // namespace collide
