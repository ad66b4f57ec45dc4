#pragma once
/// @file
/// Point queries: the closest point on a shape's surface to a point, the signed distance, and
/// the Voronoi region (closest feature) the point lies in (the lesson's "Voronoi Regions";
/// Ericson, Real-Time Collision Detection, 5.1).

#include <collide/narrow/manifold.hpp>
#include <collide/shape/shape2d.hpp>

namespace collide {

/// Result of a point query in D dimensions. World space.
template <int D>
struct PointQueryN {
  bool inside = false;      ///< the point lies strictly inside the solid shape
  float distance = 0.0f;    ///< signed distance to the surface: negative inside, world units
  VecN<D> closest{0.0f};    ///< closest point on the surface
  /// Voronoi feature of the core the point lies in: the feature whose region holds the point
  /// outside the core; inside a polygon's core, the edge of least penetration. Feature indices
  /// as in manifold.hpp (Circle: face 0. Capsule and segment: vertex 0 (end a), vertex 1
  /// (end b), edge 0 (the side to the right of a -> b), edge 1 (the side to the right of
  /// b -> a). Polygon: vertex i, or edge i from vertex i to i + 1).
  Feature feature{};
};

using PointQuery = PointQueryN<2>;   ///< 2D point query
using PointQuery3 = PointQueryN<3>;  ///< 3D point query

/// Closest surface point of shape placed by `xf` to world point `point`, with signed distance
/// and Voronoi feature; radii (circles, capsules, rounded polygons) applied along the direction
/// from the core's closest point to `point`. Ties: a point on a segment or capsule core is in
/// edge 0; the centre of a circle gets the closest point in local +x. A segment has no inside
/// (distance >= 0). Shapes must be valid; `point` and `xf` finite. O(n) for polygons: the edge
/// of greatest separation, then a walk through the Voronoi regions (Ericson 5.1.2-5.1.5).
template <Shape2DType S>
[[nodiscard]] PointQuery closest_point(const S& shape, const Transform& xf, Vec2 point) noexcept;

/// `closest_point` for a shape whose type is known only at run time.
[[nodiscard]] PointQuery closest_point(const Shape2D& shape, const Transform& xf,
                                       Vec2 point) noexcept;

}  // namespace collide
